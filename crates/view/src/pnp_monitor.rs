//! PNP's monitor line, as the PNP library's `ConnectionObserver` writes it
//! (iocchi/PetriNetPlans, `PNP/src/connection_observer.cpp`): on every
//! marking change a line `planname[n1,n2,...]` to the connected client, the
//! token counts taken from a `std::map` keyed by the places' node ids, so in
//! the byte order of those ids, the line ended by `std::endl`. The PNP
//! library listens on TCP port 47996 of every interface and serves one
//! client; this one listens on loopback unless told otherwise, and writes to
//! every client connected.

use std::io::Write;
use std::net::TcpStream;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use learnpnp_feed::{MarkingSample, PlanShape};

/// PNP's `ConnectionObserver` port.
pub const PNP_MONITOR_PORT: u16 = 47996;

/// How long a write to a monitor client may block before the client is dropped.
const WRITE_TIMEOUT: Duration = Duration::from_millis(100);

/// The connected clients.
pub(crate) type Clients = Arc<Mutex<Vec<TcpStream>>>;

/// Accepts monitor clients forever (until the runtime stops).
pub(crate) async fn accept(listener: tokio::net::TcpListener, clients: Clients) {
    loop {
        let Ok((socket, _)) = listener.accept().await else {
            continue;
        };
        let Ok(socket) = socket.into_std() else {
            continue;
        };
        if socket.set_nonblocking(false).is_ok() && socket.set_write_timeout(Some(WRITE_TIMEOUT)).is_ok() {
            clients.lock().unwrap_or_else(PoisonError::into_inner).push(socket);
        }
    }
}

/// How one plan's markings are written as monitor lines.
#[derive(Debug, Clone)]
pub(crate) struct LineFormat {
    plan: String,
    /// Place indices in the order of their node ids.
    order: Vec<usize>,
}

impl LineFormat {
    /// The format of `shape`'s markings.
    pub(crate) fn new(shape: &PlanShape) -> Self {
        let mut order: Vec<usize> = (0..shape.places.len()).collect();
        order.sort_by(|&a, &b| {
            shape.places[a]
                .file_id
                .as_bytes()
                .cmp(shape.places[b].file_id.as_bytes())
        });
        LineFormat {
            plan: shape.plan.clone(),
            order,
        }
    }

    /// The line of `marking`, newline included.
    pub(crate) fn line(&self, marking: &MarkingSample) -> String {
        let counts: Vec<String> = self
            .order
            .iter()
            .map(|&i| marking.tokens.get(i).copied().unwrap_or(0).to_string())
            .collect();
        format!("{}[{}]\n", self.plan, counts.join(","))
    }
}

/// Writes `line` to every client, dropping those that fail or block.
pub(crate) fn broadcast(clients: &Clients, line: &str) {
    let mut clients = clients.lock().unwrap_or_else(PoisonError::into_inner);
    clients.retain_mut(|client| client.write_all(line.as_bytes()).is_ok());
}

#[cfg(test)]
mod tests {
    use super::*;
    use learnpnp_feed::{PlaceShape, Source};

    #[test]
    fn places_are_ordered_by_node_id_as_a_std_map_orders_them() {
        let place = |id: u32, file_id: &str| PlaceShape {
            id,
            label: format!("l{id}"),
            file_id: file_id.into(),
        };
        let shape = PlanShape {
            source: Source { run: 0, agent: 0 },
            plan: "kick".into(),
            places: vec![place(0, "p2"), place(1, "p10"), place(2, "p1")],
            transitions: Vec::new(),
        };
        let marking = MarkingSample {
            source: shape.source.clone(),
            sub_plan: None,
            episode: 0,
            step: 0,
            tokens: vec![1, 2, 3],
            marked: Vec::new(),
            running: Vec::new(),
        };
        assert_eq!(LineFormat::new(&shape).line(&marking), "kick[3,2,1]\n");
    }
}
