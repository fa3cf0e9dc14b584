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
}

impl LinkReport {
    /// The report in `dir`, if there is a readable one.
    pub fn read(dir: &Path) -> Option<LinkReport> {
        let bytes = std::fs::read(dir.join(LINK_REPORT_FILE)).ok()?;
        serde_json::from_slice(&bytes).ok()
    }

    /// Writes it into `dir` (atomically).
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        let json = serde_json::to_vec_pretty(self).map_err(std::io::Error::other)?;
        atomic_file::write_atomic(&dir.join(LINK_REPORT_FILE), &json)
    }
}
