//! What a run produced: its [`RunRecord`] (faults, restarts and resumes,
//! histograms, refusals, the learners' final values), collected from the
//! processes' files once the run has stopped; how exits and logs read in it.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitStatus;

use serde::Serialize;

use super::config::{SupervisorError, io_error, json_error};
use super::watch::{Fault, Watch};
use crate::hosts::report::LinkReport;
use crate::ipc::convert::Rejections;
use crate::ipc::protocol::{Role, Roster};
use crate::latency::Latency;
use crate::multiprocess::agent::chassis::{checkpoint_name, resumed_file};
use crate::multiprocess::agent::keeper::roster_compute_histogram;
use crate::multiprocess::agent::world::{WORLD_TURNAROUND, agent_result_file};
use crate::multiprocess::floor_probe::REMOTE_HOST_FLOOR;
use crate::multiprocess::host::simulator::{
    FLOOR, RESULT_FILE, ROUND_TRIP, SimulatorResult, keeper_round_trip_histogram,
};
use crate::multiprocess::view_process::ViewCounts;
use learnpnp::learning::persist::{self, SavedValues};

/// Whether a restarted agent resumed with exactly the values checkpointed
/// before it was lost.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResumeCheck {
    /// The run.
    pub run: usize,
    /// The keeper (1-based).
    pub keeper: usize,
    /// The replacement's process id.
    pub pid: u32,
    /// What it should have loaded: "checkpoint", or "previous checkpoint" when
    /// the last one was unusable.
    pub source: String,
    /// It loaded exactly those values.
    pub survived: bool,
}

/// What one run of the system produced.
#[derive(Debug)]
pub struct RunRecord {
    /// The run's index.
    pub run: usize,
    /// The simulator's result (protocol output, counters); empty if it died.
    pub sim: SimulatorResult,
    /// Why the run did not complete normally (a process the run cannot do
    /// without died, or could not be restarted).
    pub failure: Option<String>,
    /// Faults and restarts, in order.
    pub faults: Vec<Fault>,
    /// Processes restarted (agents and, in chaos soaks, the simulator).
    pub restarts: u32,
    /// For each agent restart: did it resume with the checkpointed values?
    pub resumes: Vec<ResumeCheck>,
    /// The run's histograms: round trip, floor, and each keeper's compute time.
    pub histograms: Vec<Latency>,
    /// Messages refused, by process (the simulator and each keeper, all incarnations).
    pub rejected: BTreeMap<String, Rejections>,
    /// Real time: the cycles whose work ran past their deadline, by process
    /// that keeps a cycle (the simulator, or the world: all incarnations).
    pub late_cycles: BTreeMap<String, u64>,
    /// Checkpoint writes that failed, over every agent.
    pub(crate) checkpoint_failures: u64,
    /// The learning keepers' final values (their last checkpoints).
    pub values: Vec<SavedValues>,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
    /// Files of the run's namespace left after cleanup (0 unless cleanup failed).
    pub leftover_files: usize,
    /// The run's iceoryx2 prefix.
    pub prefix: String,
    /// How the simulator and the agents were scheduled.
    pub(crate) scheduling: String,
    /// A run across hosts: what this host's bridge carried and refused.
    pub link: Option<LinkReport>,
    /// A run with a view: what it read of the agents' feeds, refused and lost.
    pub view: Option<ViewCounts>,
}

/// How an exit status reads in a report.
pub(super) fn describe(status: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(code), _) => format!("exit code {code}"),
        (None, Some(signal)) => format!("signal {signal} ({})", signal_name(signal)),
        _ => status.to_string(),
    }
}

pub(super) fn signal_name(signal: i32) -> &'static str {
    match signal {
        libc::SIGKILL => "SIGKILL",
        libc::SIGTERM => "SIGTERM",
        libc::SIGSEGV => "SIGSEGV",
        libc::SIGABRT => "SIGABRT",
        libc::SIGINT => "SIGINT",
        _ => "signal",
    }
}

/// The last lines of a log, for an error message.
/// The last non-empty line of the log at `path` ("(empty log)" if none).
pub(super) fn last_log_line(path: &Path) -> String {
    let text = fs::read_to_string(path).unwrap_or_default();
    text.lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .map_or_else(|| "(empty log)".to_string(), |l| l.trim().to_string())
}

pub(super) fn log_tail(path: &Path) -> String {
    let text = fs::read_to_string(path).unwrap_or_default();
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    lines[lines.len().saturating_sub(3)..].join(" | ")
}

/// Reads every histogram the processes of a run of `roster` wrote into
/// `dir`, the incarnations of each process merged (`<name>.<pid>.hdr`); a
/// file that cannot be read or decoded is left out, and said in the second
/// list (the run's report never fails for one file).
pub(super) fn read_histograms(dir: &Path, roster: Roster) -> Result<(Vec<Latency>, Vec<String>), SupervisorError> {
    let mut files: Vec<PathBuf> = fs::read_dir(dir)
        .map_err(io_error(dir))?
        .flatten()
        .map(|e| e.path())
        .collect();
    files.sort();
    let compute = |k| roster_compute_histogram(roster, k);
    let per_roster: Vec<String> = match roster {
        Roster::Keepaway => (0..roster.agents()).map(keeper_round_trip_histogram).collect(),
        Roster::World { .. } => vec![WORLD_TURNAROUND.to_string()],
    };
    let names = [ROUND_TRIP.to_string(), FLOOR.to_string(), REMOTE_HOST_FLOOR.to_string()]
        .into_iter()
        .chain((0..roster.agents()).map(compute))
        .chain(per_roster);
    let mut histograms = Vec::new();
    let mut unreadable = Vec::new();
    for name in names {
        let mut merged = Latency::new(name.clone());
        for path in &files {
            let file = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            if file.starts_with(&format!("{name}.")) && file.ends_with(".hdr") {
                let read = fs::read(path)
                    .map_err(|e| e.to_string())
                    .and_then(|bytes| Latency::from_bytes(name.clone(), &bytes).map_err(|e| e.to_string()))
                    .and_then(|h| merged.merge(&h).map_err(|e| e.to_string()));
                if let Err(e) = read {
                    unreadable.push(format!("{}: {e}", path.display()));
                }
            }
        }
        histograms.push(merged);
    }
    Ok((histograms, unreadable))
}

impl Watch<'_> {
    /// What the stopped run produced, given how watching it ended.
    pub(super) fn collect(
        mut self,
        watched: Result<ExitStatus, SupervisorError>,
    ) -> Result<RunRecord, SupervisorError> {
        let failure = self.failure(watched)?;
        let seconds = self.started.elapsed().as_secs_f64();
        let mut sim = self.simulator_result(failure.is_some())?;
        sim.totals.missed_deadlines += self.world_missed_deadlines();
        let host = match self.roster {
            Roster::Keepaway => "the simulator",
            Roster::World { .. } => "agent 1",
        };
        let failure = failure.or_else(|| self.findings.stalled.clone()).or_else(|| {
            let stopped = self.stop_requested;
            sim.error
                .clone()
                .filter(|_| !stopped)
                .map(|e| format!("{host} ended the run early: {e}"))
        });
        let learning = match self.roster {
            Roster::Keepaway => {
                crate::multiprocess::host::simulator::keepaway_config(&self.config.spec)?.learning_keepers()
            }
            Roster::World { agents } => agents,
        };
        let values = self.final_values(learning, failure.is_some());
        let checkpoint_failures = self.heard.pulses.values().map(|p| p.checkpoint_failures).sum();
        let link = self.link_faults(&sim);
        if let Some(floor) = &self.floor {
            floor.save()?;
        }
        let (histograms, unreadable) = read_histograms(&self.context.work_dir, self.roster)?;
        for problem in unreadable {
            self.fault(
                format!("a histogram cannot be read: {problem}"),
                "left out of the report".into(),
            );
        }
        let work_dir = &self.context.work_dir;
        Ok(RunRecord {
            run: self.context.run,
            rejected: self.rejected(&sim),
            late_cycles: self.late_cycles(&sim),
            sim,
            failure,
            restarts: self.restarts.counts.values().sum::<u32>(),
            resumes: self.resume_checks(learning),
            faults: std::mem::take(&mut self.findings.faults),
            histograms,
            checkpoint_failures,
            values,
            seconds,
            leftover_files: 0,
            prefix: String::new(),
            scheduling: self.scheduling(),
            link,
            view: self.config.view.as_ref().map(|_| ViewCounts::load(work_dir)),
        })
    }

    /// Why the run failed, if it did, from how watching it ended (an error
    /// other than a process's failure is the supervisor's own, returned).
    pub(super) fn failure(
        &mut self,
        watched: Result<ExitStatus, SupervisorError>,
    ) -> Result<Option<String>, SupervisorError> {
        Ok(match watched {
            Ok(status) if status.success() => None,
            Ok(status) => {
                let host = self.roster.host();
                let what = format!("the {host} exited: {}", describe(status));
                self.fault(what.clone(), "agents stopped; run given up".into());
                Some(format!("{what} ({})", log_tail(&self.log(host))))
            }
            Err(SupervisorError::Run(failure)) => Some(failure.to_string()),
            Err(other) => return Err(other),
        })
    }

    /// The simulator's result file, or in a world run agent 1's (empty if
    /// the run failed before it was written).
    pub(super) fn simulator_result(&self, failed: bool) -> Result<SimulatorResult, SupervisorError> {
        let file = match self.roster {
            Roster::Keepaway => RESULT_FILE.to_string(),
            Roster::World { .. } => agent_result_file(0),
        };
        let result_path = self.context.work_dir.join(file);
        match fs::read_to_string(&result_path) {
            Ok(text) => serde_json::from_str(&text).map_err(json_error(result_path.display())),
            Err(_) if failed => Ok(SimulatorResult::default()),
            Err(source) => Err(SupervisorError::Io {
                path: result_path,
                source,
            }),
        }
    }

    /// The `learning` keepers' last checkpoints, up to the first that does
    /// not load (a fault naming it, unless the run failed: then its agents
    /// may not have written theirs).
    pub(super) fn final_values(&mut self, learning: usize, failed: bool) -> Vec<SavedValues> {
        let mut values = Vec::new();
        for k in 0..learning {
            let path = self.context.work_dir.join(checkpoint_name(k));
            match persist::load(&path) {
                Ok(v) => values.push(v),
                Err(e) => {
                    if !failed {
                        self.fault(
                            format!("keeper {}'s final values cannot be read: {e}", k + 1),
                            "the report lacks its values and those of the keepers after it".into(),
                        );
                    }
                    break;
                }
            }
        }
        values
    }

    /// For each agent restarted: did it resume with the checkpointed values?
    pub(super) fn resume_checks(&self, learning: usize) -> Vec<ResumeCheck> {
        self.restarts
            .pending_resumes
            .iter()
            .filter(|r| r.expected.is_some() || r.keeper < learning)
            .map(|r| {
                let loaded = persist::load(&resumed_file(&self.context.work_dir, r.keeper, r.pid)).ok();
                let (source, survived) = match &r.expected {
                    Some((values, source)) => (source.to_string(), loaded.as_ref() == Some(values)),
                    None => ("none usable".to_string(), false),
                };
                ResumeCheck {
                    run: self.context.run,
                    keeper: r.keeper + 1,
                    pid: r.pid,
                    source,
                    survived,
                }
            })
            .collect()
    }

    /// Messages refused, summed over every incarnation of each process
    /// (the simulator's from its result, the others' from their last heartbeats).
    pub(super) fn rejected(&self, sim: &SimulatorResult) -> BTreeMap<String, Rejections> {
        let mut by_process: BTreeMap<String, Rejections> = BTreeMap::new();
        if self.roster == Roster::Keepaway {
            by_process.insert(Role::Simulator.to_string(), sim.totals.rejected);
        }
        for ((role, _), pulse) in &self.heard.pulses {
            if *role != Role::Simulator {
                let entry = by_process.entry(role.to_string()).or_default();
                *entry = entry.plus(&pulse.rejected);
            }
        }
        by_process
    }

    /// The late cycles of the process that keeps the run's cycle: the
    /// simulator's from its result, the world's summed over its
    /// incarnations' last heartbeats.
    pub(super) fn late_cycles(&self, sim: &SimulatorResult) -> BTreeMap<String, u64> {
        let role = self.roster.host();
        let late = match role {
            Role::Simulator => sim.totals.late_cycles,
            _ => self
                .heard
                .pulses
                .iter()
                .filter(|((r, _), _)| *r == role)
                .map(|(_, pulse)| pulse.late_cycles)
                .sum(),
        };
        BTreeMap::from([(role.to_string(), late)])
    }

    /// World runs: the deadlines the world's incarnations missed.
    pub(super) fn world_missed_deadlines(&self) -> u64 {
        self.heard
            .pulses
            .iter()
            .filter(|((role, _), _)| *role == Role::World)
            .map(|(_, pulse)| pulse.missed_deadlines)
            .sum()
    }
}
