//! The live view's flags (`--view`, `--record-mcap`, `--pnp-monitor`), shared
//! by `learnpnp experiment` and the multi-process supervisor.

use std::net::SocketAddr;
use std::path::PathBuf;

use clap::Args;

/// Where a run's live feed goes; nothing is served or written unless asked.
#[derive(Args, Debug, Clone, Default)]
pub struct ViewFlags {
    /// Serve the live view (the page, and the Foxglove WebSocket protocol) on
    /// ADDR (default 127.0.0.1:8765; port 0 picks a free port; another
    /// interface than loopback only when given).
    #[arg(long, value_name = "ADDR", num_args = 0..=1, require_equals = true,
          default_missing_value = "127.0.0.1:8765")]
    pub view: Option<SocketAddr>,
    /// Record the live feed's channels to an MCAP file (written as FILE.part,
    /// renamed to FILE when the run ends).
    #[arg(long, value_name = "FILE")]
    pub record_mcap: Option<PathBuf>,
    /// Write PNP's monitor line (`plan[n1,n2,...]` per marking, as the PNP
    /// library's ConnectionObserver) to TCP clients on ADDR (default
    /// 127.0.0.1:47996).
    #[arg(long, value_name = "ADDR", num_args = 0..=1, require_equals = true,
          default_missing_value = "127.0.0.1:47996")]
    pub pnp_monitor: Option<SocketAddr>,
}

impl ViewFlags {
    /// Whether any flag asks for the view.
    pub fn asked(&self) -> bool {
        self.view.is_some() || self.record_mcap.is_some() || self.pnp_monitor.is_some()
    }
}
