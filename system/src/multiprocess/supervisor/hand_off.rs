//! The hand-off to other hosts (a run across hosts, seen from host A): the
//! run's description for them, this host's bridge (`learnpnp-bridge`, a
//! process of its own) and its link report, and the wait for the remote
//! agents' files once the run is over.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use super::config::{Cluster, SupervisorError, json_error};
use super::watch::Watch;
use crate::hosts::report::LinkReport;
use crate::hosts::shipped::HOST_B_LINK_REPORT;
use crate::ipc::protocol::{Order, Role, Roster};
use crate::multiprocess::agent::chassis::checkpoint_name;
use crate::multiprocess::agent::world::agent_result_file;
use crate::multiprocess::host::simulator::SimulatorResult;

/// How often host A tells the other hosts again to stop while it waits for their files.
pub(super) const RESTOP_EVERY: Duration = Duration::from_secs(1);

/// How long a bridge asked to stop may take to write its last link report.
pub const BRIDGE_STOP_GRACE: Duration = Duration::from_secs(2);

/// The file of a run's work directory describing it to the other hosts.
pub const RUN_INFO_FILE: &str = "run-info.json";

/// How long host A waits, once the run is over, for the remote agents' files.
pub const REMOTE_FILES_TIMEOUT: Duration = Duration::from_secs(30);

impl Watch<'_> {
    /// The bridge's command line: this host's namespace, the link, the run's description.
    pub(super) fn bridge_args(&self) -> Vec<std::ffi::OsString> {
        let mut args: Vec<std::ffi::OsString> = vec![
            "--ipc-prefix".into(),
            self.context.ipc_prefix.clone().into(),
            "--side".into(),
            "host".into(),
            "--run-info".into(),
            self.context.work_dir.join(RUN_INFO_FILE).into(),
            "--work-dir".into(),
            self.context.work_dir.clone().into(),
        ];
        if let Some(cluster) = &self.config.cluster {
            for endpoint in &cluster.listen {
                args.push("--listen".into());
                args.push(endpoint.into());
            }
            match &cluster.link_certs {
                Some(dir) => args.extend(["--link-certs".into(), dir.clone().into_os_string()]),
                None => args.push("--insecure-plain-tcp".into()),
            }
        }
        args
    }

    /// Writes the run's description the bridge gives the other hosts.
    pub(super) fn describe_for_other_hosts(&self, cluster: &Cluster) -> Result<(), SupervisorError> {
        let info = crate::hosts::run_info::RunInfo {
            prefix: self.context.ipc_prefix.clone(),
            run_id: self.context.run_id,
            run: self.context.run,
            roster: self.roster,
            remote: cluster.remote.clone(),
            clock: self.config.clock,
            wait: self.config.wait,
            checkpoint_every: self.config.checkpoint_every,
            floor_round_trips: self.config.floor_round_trips,
            spec: serde_json::to_value(&self.config.spec).map_err(json_error("the experiment spec"))?,
        };
        let path = self.context.work_dir.join(RUN_INFO_FILE);
        info.write(&path).map_err(|e| SupervisorError::Bridge(e.to_string()))
    }

    /// Whether agent `k` runs on another host.
    pub(super) fn is_remote(&self, k: usize) -> bool {
        self.config.cluster.as_ref().is_some_and(|c| c.remote.contains(&k))
    }

    /// Host A, once the run is over: waits for the remote agents' files
    /// (their last checkpoints and histograms, shipped by their host's
    /// bridge), then stops the bridge.
    pub(super) fn await_remote_files(&mut self) -> Result<(), SupervisorError> {
        let Some(cluster) = &self.config.cluster else {
            return Ok(());
        };
        let learning = self.learning_agents()?;
        let mut expected: Vec<PathBuf> = cluster
            .remote
            .iter()
            .filter(|&&k| k < learning)
            .map(|&k| self.context.work_dir.join(checkpoint_name(k)))
            .collect();
        if self.roster != Roster::Keepaway && cluster.remote.contains(&0) {
            // A world run's report is agent 1's result.
            expected.push(self.context.work_dir.join(agent_result_file(0)));
        }
        let deadline = Instant::now() + REMOTE_FILES_TIMEOUT;
        let arrived = |expected: &[PathBuf]| expected.iter().all(|p| p.is_file());
        let mut ordered = Instant::now();
        while !arrived(&expected) && Instant::now() < deadline {
            // The stop is told again: a host B whose link was down when it
            // was first told (its peer's bridge restarted; over QUIC a dead
            // peer is noticed only when its lease expires) hears it once
            // the link is back.
            if ordered.elapsed() >= RESTOP_EVERY {
                self.order(Order::Stop, None)?;
                ordered = Instant::now();
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        if !arrived(&expected) {
            self.fault(
                format!(
                    "the remote agents' checkpoints did not arrive within {} s",
                    REMOTE_FILES_TIMEOUT.as_secs()
                ),
                "the report lacks their values".into(),
            );
        }
        // The histograms come in the same shipment, just after the checkpoints.
        std::thread::sleep(Duration::from_millis(500));
        if let Some(mut bridge) = self.fleet.processes.remove(&Role::Bridge) {
            // Asked to stop, it writes its last link report.
            let _ = bridge.stop(BRIDGE_STOP_GRACE);
        }
        Ok(())
    }

    /// A run across hosts: the bridge's link report, and as faults what
    /// must not pass for a clean run (plain TCP, refusals on the link, a
    /// stop ordered from another host); in lock-step, commands out of
    /// sequence (forged or displaced: a cycle answered twice).
    pub(super) fn link_faults(&mut self, sim: &SimulatorResult) -> Option<LinkReport> {
        if sim.totals.displaced_commands > 0 {
            self.fault(
                format!(
                    "{} keeper commands out of sequence in lock-step (forged, or displaced by a forged one)",
                    sim.totals.displaced_commands
                ),
                "the episodes may not be the keepers' own".into(),
            );
        }
        self.config.cluster.as_ref()?;
        let mut link = LinkReport::read(&self.context.work_dir).unwrap_or_default();
        // Host B's own counts, shipped with its files (checked on arrival).
        link.host_b = LinkReport::read_file(&self.context.work_dir.join(HOST_B_LINK_REPORT))
            .ok()
            .map(Box::new);
        if let Some(warning) = &link.warning {
            self.fault(warning.clone(), "run as asked".into());
        }
        self.link_traffic_faults(&link, ["the bridge", "host B", "host A", "the run"]);
        if link.stop_requests > 0 {
            self.fault(
                "host B's supervisor ordered the run to stop".into(),
                "the run was stopped".into(),
            );
        }
        for file in &link.refused_files {
            self.fault(
                format!(
                    "host B's file '{}' refused ({}): {}",
                    file.name, file.reason, file.detail
                ),
                "not written into the run; host A reports without it".into(),
            );
        }
        self.agents_lost_faults(&link, sim);
        if let Some(b) = &link.host_b {
            self.link_traffic_faults(b, ["host B's bridge", "host A", "host B", "host B's agents"]);
        }
        Some(link)
    }

    /// What one host's bridge refused and lost, as faults: `[whose bridge,
    /// the other host, this host, what its messages are for]`.
    fn link_traffic_faults(&mut self, link: &LinkReport, [bridge, other, this, reached]: [&str; 4]) {
        if link.refused.total() > 0 {
            self.fault(
                format!(
                    "{bridge} refused {} messages or peers on the link: {:?}",
                    link.refused.total(),
                    link.refused
                ),
                format!("none of them reached {reached}"),
            );
        }
        if link.lost > 0 {
            self.fault(
                format!(
                    "{} messages from {other} never reached {this} (gaps in their sequence numbers)",
                    link.lost
                ),
                format!("{reached} went on without them"),
            );
        }
    }

    /// Every report from host B that one of its agents was lost, as a fault:
    /// passed on, with the episode it aborted; or refused, with why.
    fn agents_lost_faults(&mut self, link: &LinkReport, sim: &SimulatorResult) {
        let mut aborted = sim.totals.aborted.iter();
        for event in &link.agents_lost {
            let what = format!(
                "host B reported agent {} lost (replacement process {})",
                event.agent, event.pid
            );
            let outcome = if event.accepted {
                let episode = aborted.by_ref().find(|a| a.keepers.contains(&event.agent)).map_or_else(
                    || "no episode aborted".to_string(),
                    |a| format!("episode {} aborted", a.episode),
                );
                format!("passed on ({}): {episode}", event.why)
            } else {
                format!("refused as a forbidden order: {}", event.why)
            };
            self.fault(what, outcome);
        }
    }
}
