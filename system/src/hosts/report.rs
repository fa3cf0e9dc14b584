//! What a host's bridges did over a run ([`LinkReport`](crate::hosts::report::LinkReport), `link.json` in the
//! host's work directory): the bridge writes it, the host's supervisor reads
//! it into its report.

use std::path::Path;

use serde::{Deserialize, Serialize};

/// The file, in the host's work directory, where its bridge keeps its [`LinkReport`].
pub const LINK_REPORT_FILE: &str = "link.json";

/// Refused by a bridge, counted by reason.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct LinkRefusals {
    /// Peers refused at the TLS handshake (no certificate, another CA's, an
    /// expired one).
    pub tls_handshake: u64,
    /// Messages and declarations host A's access control denied (a peer
    /// publishing or subscribing where its certificate may not).
    pub access_denied: u64,
    /// Messages of another type or protocol version.
    pub wrong_type: u64,
    /// Messages of the wrong size.
    pub wrong_size: u64,
    /// Messages under a key the route does not carry (a sender of another host).
    pub wrong_key: u64,
    /// Messages whose sender is not the one their key names.
    pub wrong_sender: u64,
    /// Control orders the other host may not give.
    pub forbidden_order: u64,
    /// Files under a name the run does not expect.
    pub file_name: u64,
    /// Messages of another run (the header's run id).
    #[serde(default)]
    pub wrong_run: u64,
    /// Messages whose content the receiving process would refuse (an
    /// unknown kind or tag, an id out of range, a number that is not finite).
    #[serde(default)]
    pub bad_content: u64,
    /// Files whose content is not what their name says (a histogram that
    /// does not decode, a value file that does not load or is of another
    /// plan, a report that does not parse).
    #[serde(default)]
    pub file_content: u64,
    /// Files over the size cap of their kind.
    #[serde(default)]
    pub file_size: u64,
    /// Files past the count cap of their name's pattern.
    #[serde(default)]
    pub file_count: u64,
}

impl LinkRefusals {
    /// All refusals.
    pub fn total(&self) -> u64 {
        self.tls_handshake
            + self.access_denied
            + self.wrong_type
            + self.wrong_size
            + self.wrong_key
            + self.wrong_sender
            + self.forbidden_order
            + self.file_name
            + self.wrong_run
            + self.bad_content
            + self.file_content
            + self.file_size
            + self.file_count
    }

    /// The sum, reason by reason.
    pub fn plus(&self, o: &LinkRefusals) -> LinkRefusals {
        LinkRefusals {
            tls_handshake: self.tls_handshake + o.tls_handshake,
            access_denied: self.access_denied + o.access_denied,
            wrong_type: self.wrong_type + o.wrong_type,
            wrong_size: self.wrong_size + o.wrong_size,
            wrong_key: self.wrong_key + o.wrong_key,
            wrong_sender: self.wrong_sender + o.wrong_sender,
            forbidden_order: self.forbidden_order + o.forbidden_order,
            file_name: self.file_name + o.file_name,
            wrong_run: self.wrong_run + o.wrong_run,
            bad_content: self.bad_content + o.bad_content,
            file_content: self.file_content + o.file_content,
            file_size: self.file_size + o.file_size,
            file_count: self.file_count + o.file_count,
        }
    }
}

/// What a host's bridges did over the run (summed over restarts): its
/// supervisor copies it into the host's `summary.json`.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct LinkReport {
    /// `mutual-tls-quic` or `plain-tcp`.
    pub security: String,
    /// What plain TCP gives up, when the link is plain TCP.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
    /// Messages sent to the other hosts.
    pub sent: u64,
    /// Messages received and published here.
    pub received: u64,
    /// Files shipped or received.
    pub files: u64,
    /// The other host asked this one to stop the run (host A: a STOP order
    /// from host B's supervisor, which may give it).
    pub stop_requests: u64,
    /// Refusals by reason.
    pub refused: LinkRefusals,
    /// Messages from the other host that never arrived: gaps in the
    /// sequence numbers of a carried service (dropped on a congested link,
    /// or lost with a connection).
    #[serde(default)]
    pub lost: u64,
    /// The files refused, with why (the first [`MAX_LISTED`] of them).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub refused_files: Vec<RefusedFile>,
    /// Every agent the other host reported lost, and what this host made
    /// of it (the first [`MAX_LISTED`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub agents_lost: Vec<AgentLost>,
    /// Host A: the other host's own link report, shipped with its files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub host_b: Option<Box<LinkReport>>,
}

/// The most files or reports of lost agents a [`LinkReport`] lists (the counts go on).
pub const MAX_LISTED: usize = 100;

/// A file the other host shipped that was refused.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RefusedFile {
    /// Its name.
    pub name: String,
    /// Why: `file_name`, `file_content`, `file_size` or `file_count`.
    pub reason: String,
    /// What was wrong with it.
    pub detail: String,
}

/// The other host's report that one of its agents was lost (`KEEPER_LOST`),
/// and whether this host acted on it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AgentLost {
    /// The agent (1-based: keeper 3 is 3).
    pub agent: usize,
    /// The process id the report names (the agent's replacement).
    pub pid: u32,
    /// Whether this host passed it on (its own view agreed).
    pub accepted: bool,
    /// Why it was passed on, or refused.
    pub why: String,
}

impl LinkReport {
    /// The sum of two reports of the same host (runs, or bridges' lives).
    pub fn plus(&self, o: &LinkReport) -> LinkReport {
        let listed = |a: &[RefusedFile], b: &[RefusedFile]| a.iter().chain(b).take(MAX_LISTED).cloned().collect();
        LinkReport {
            security: self.security.clone(),
            warning: self.warning.clone(),
            sent: self.sent + o.sent,
            received: self.received + o.received,
            files: self.files + o.files,
            stop_requests: self.stop_requests + o.stop_requests,
            refused: self.refused.plus(&o.refused),
            lost: self.lost + o.lost,
            refused_files: listed(&self.refused_files, &o.refused_files),
            agents_lost: self
                .agents_lost
                .iter()
                .chain(&o.agents_lost)
                .take(MAX_LISTED)
                .cloned()
                .collect(),
            host_b: match (&self.host_b, &o.host_b) {
                (Some(a), Some(b)) => Some(Box::new(a.plus(b))),
                (a, b) => a.clone().or_else(|| b.clone()),
            },
        }
    }
}

impl LinkReport {
    /// The report in `dir`, if there is a readable one.
    pub fn read(dir: &Path) -> Option<LinkReport> {
        LinkReport::read_file(&dir.join(LINK_REPORT_FILE)).ok()
    }

    /// The report in the file at `path`.
    pub fn read_file(path: &Path) -> std::io::Result<LinkReport> {
        let bytes = std::fs::read(path)?;
        serde_json::from_slice(&bytes).map_err(std::io::Error::other)
    }

    /// What on the link explains a lock-step stall, if anything does: a
    /// report of a lost agent refused, messages lost, orders refused.
    pub fn stall_cause(&self) -> Option<String> {
        let mut causes = Vec::new();
        for lost in self.agents_lost.iter().filter(|l| !l.accepted) {
            causes.push(format!(
                "host B reported agent {} lost (process {}) and host A refused it: {}",
                lost.agent, lost.pid, lost.why
            ));
        }
        let lost = self.lost + self.host_b.as_ref().map_or(0, |b| b.lost);
        if lost > 0 {
            causes.push(format!("{lost} messages between the hosts never arrived"));
        }
        if self.refused.forbidden_order + self.refused.bad_content + self.refused.wrong_run > 0 {
            causes.push(format!(
                "host A's bridge refused messages from host B: {:?}",
                self.refused
            ));
        }
        (!causes.is_empty()).then(|| causes.join("; "))
    }

    /// Writes it into `dir` (atomically).
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        let json = serde_json::to_vec_pretty(self).map_err(std::io::Error::other)?;
        atomic_file::write_atomic(&dir.join(LINK_REPORT_FILE), &json)
    }
}
