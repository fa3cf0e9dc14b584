//! The files host B ships to host A at the end of a run ([`ShippedFiles`](crate::hosts::shipped::ShippedFiles)):
//! which names may arrive, how large and how many, and what each must hold
//! ([`FileKind::check`](crate::hosts::shipped::FileKind::check)). Host A's result never depends on one of them being
//! good: its bridge writes what arrives into a quarantine beside the run,
//! checks it there, and moves it into the run only if it passed; anything
//! else is refused and counted, and host A reports without it.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

use learnpnp::experiment::spec::{DomainSpec, ExperimentSpec};
use learnpnp::learning::persist::{self, PlanLabels};

use super::report::{LinkRefusals, LinkReport, MAX_LISTED, RefusedFile};
use super::run_info::RunInfo;
use crate::ipc::protocol::Roster;
use crate::latency::Latency;
use crate::multiprocess::agent::chassis::checkpoint_name;
use crate::multiprocess::agent::keeper::compute_histogram;
use crate::multiprocess::agent::world::{WORLD_TURNAROUND, agent_compute_histogram, agent_result_file};
use crate::multiprocess::floor_probe::REMOTE_HOST_FLOOR;
use crate::multiprocess::host::simulator::{ROUND_TRIP, SimulatorResult};

/// The name under which host B ships its own link report.
pub const HOST_B_LINK_REPORT: &str = "link-host-b.json";

/// The directory of host A's run directory where shipped files wait to be checked.
pub const QUARANTINE: &str = "quarantine";

/// Good histograms of one process name taken into a run (one per
/// incarnation). Any other name is one file: arriving again, it replaces it
/// (if good).
pub const MAX_INCARNATIONS: usize = 64;

/// What a shipped file is, by its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// A latency histogram (`STEM.PID.hdr`, HdrHistogram V2).
    Histogram,
    /// A remote agent's checkpoint (`values-agentN.bin`) of agent `0`-based index.
    Values(usize),
    /// A world agent's result (`agentN.json`).
    AgentResult,
    /// Host B's link report ([`HOST_B_LINK_REPORT`]).
    LinkReport,
}

impl FileKind {
    /// The largest file of this kind host A takes, in bytes.
    pub fn size_cap(self) -> usize {
        match self {
            FileKind::Histogram => 16 << 20,
            FileKind::Values(_) => 512 << 20,
            FileKind::AgentResult => 64 << 20,
            FileKind::LinkReport => 4 << 20,
        }
    }

    /// Checks that `bytes` hold what a file of this kind called `name`
    /// holds; `plans` are the plans each agent learns on, as host A knows
    /// them (`None`: not known here, the plan is not compared). The error
    /// says what is wrong.
    pub fn check(self, name: &str, bytes: &[u8], plans: &BTreeMap<usize, Vec<PlanLabels>>) -> Result<(), String> {
        match self {
            FileKind::Histogram => Latency::from_bytes(name, bytes).map(|_| ()).map_err(|e| e.to_string()),
            FileKind::Values(agent) => {
                let values = persist::from_bytes(Path::new(name), bytes).map_err(|e| e.to_string())?;
                match plans.get(&agent) {
                    Some(expected) if &values.plans != expected => {
                        Err(format!("{name}: values of another plan than agent {}'s", agent + 1))
                    }
                    _ => Ok(()),
                }
            }
            FileKind::AgentResult => serde_json::from_slice::<SimulatorResult>(bytes)
                .map(|_| ())
                .map_err(|e| format!("{name}: not an agent's result: {e}")),
            FileKind::LinkReport => serde_json::from_slice::<LinkReport>(bytes)
                .map(|_| ())
                .map_err(|e| format!("{name}: not a link report: {e}")),
        }
    }
}

/// The files host B may ship to host A: its agents' checkpoints, results
/// and histograms, under the names the run gives them, and its link report;
/// nothing else (not `spec.json`, not another agent's values).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShippedFiles {
    /// Names shipped as they are.
    exact: Vec<(String, FileKind)>,
    /// Histograms, shipped as `STEM.PID.hdr`.
    histograms: Vec<String>,
}

impl ShippedFiles {
    /// The files of `info`'s remote agents.
    pub fn of(info: &RunInfo) -> Self {
        let mut exact: Vec<(String, FileKind)> = info
            .remote
            .iter()
            .map(|&a| (checkpoint_name(a), FileKind::Values(a)))
            .collect();
        exact.push((HOST_B_LINK_REPORT.to_string(), FileKind::LinkReport));
        let mut histograms = vec![REMOTE_HOST_FLOOR.to_string()];
        match info.roster {
            Roster::Keepaway => histograms.extend(info.remote.iter().map(|&k| compute_histogram(k))),
            Roster::World { .. } => {
                exact.extend(
                    info.remote
                        .iter()
                        .map(|&a| (agent_result_file(a), FileKind::AgentResult)),
                );
                histograms.extend(info.remote.iter().map(|&a| agent_compute_histogram(a)));
                histograms.extend([ROUND_TRIP.to_string(), WORLD_TURNAROUND.to_string()]);
            }
        }
        ShippedFiles { exact, histograms }
    }

    /// What a file called `name` is, if it may arrive, and the pattern it
    /// is counted under (its name, or `STEM.*.hdr` for a histogram).
    pub fn kind(&self, name: &str) -> Option<(FileKind, String)> {
        if let Some((_, kind)) = self.exact.iter().find(|(e, _)| e == name) {
            return Some((*kind, name.to_string()));
        }
        let (stem, pid) = name.strip_suffix(".hdr")?.rsplit_once('.')?;
        let histogram =
            !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()) && self.histograms.iter().any(|h| h == stem);
        histogram.then(|| (FileKind::Histogram, format!("{stem}.*.hdr")))
    }

    /// The file names as key expressions (a histogram's process id as `$*`).
    pub fn key_patterns(&self) -> Vec<String> {
        let histograms = self.histograms.iter().map(|h| format!("{h}.$*.hdr"));
        self.exact
            .iter()
            .map(|(name, _)| name.clone())
            .chain(histograms)
            .collect()
    }
}

/// Why a shipped file was refused (as [`LinkRefusals`] counts it), and what was wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileRefusal {
    /// The count it goes in: `file_name`, `file_size`, `file_count` or `file_content`.
    pub reason: &'static str,
    /// What was wrong.
    pub detail: String,
}

impl FileRefusal {
    fn new(reason: &'static str, detail: impl Into<String>) -> Self {
        FileRefusal {
            reason,
            detail: detail.into(),
        }
    }

    /// Counts it in `refused`.
    pub fn count(&self, refused: &mut LinkRefusals) {
        match self.reason {
            "file_name" => refused.file_name += 1,
            "file_size" => refused.file_size += 1,
            "file_count" => refused.file_count += 1,
            _ => refused.file_content += 1,
        }
    }
}

/// Host A's quarantine of the files host B ships: each is written into
/// [`QUARANTINE`] beside the run, checked there ([`FileKind::check`], within
/// its kind's size cap and its pattern's count cap of good files), and
/// only then moved into the run's directory. A refused file is listed (the
/// first [`MAX_LISTED`], which also stay in the quarantine to be looked at;
/// later ones are removed).
#[derive(Debug)]
pub struct Quarantine {
    work_dir: PathBuf,
    expected: ShippedFiles,
    plans: BTreeMap<usize, Vec<PlanLabels>>,
    /// The names taken into the run, by count pattern.
    taken: BTreeMap<String, BTreeSet<String>>,
    /// The files refused (the first [`MAX_LISTED`]).
    pub refused: Vec<RefusedFile>,
}

impl Quarantine {
    /// The quarantine of `info`'s run, whose directory is `work_dir`.
    pub fn new(info: &RunInfo, work_dir: &Path) -> Self {
        Quarantine {
            work_dir: work_dir.to_path_buf(),
            expected: ShippedFiles::of(info),
            plans: expected_plans(info),
            taken: BTreeMap::new(),
            refused: Vec::new(),
        }
    }

    /// Takes one file that arrived: `Ok(Ok(()))` once it is in the run,
    /// `Ok(Err(why))` if it was refused (and listed); `Err` if this host
    /// cannot write.
    pub fn take(&mut self, name: &str, bytes: &[u8]) -> std::io::Result<Result<(), FileRefusal>> {
        let taken = self.check_and_move(name, bytes)?;
        if let Err(refusal) = &taken {
            if self.refused.len() < MAX_LISTED {
                eprintln!(
                    "bridge: refused the file '{name}' from host B ({}): {}",
                    refusal.reason, refusal.detail
                );
                self.refused.push(RefusedFile {
                    name: name.to_string(),
                    reason: refusal.reason.to_string(),
                    detail: refusal.detail.clone(),
                });
            } else {
                let _ = fs::remove_file(self.work_dir.join(QUARANTINE).join(name));
            }
        }
        Ok(taken)
    }

    fn check_and_move(&mut self, name: &str, bytes: &[u8]) -> std::io::Result<Result<(), FileRefusal>> {
        let Some((kind, pattern)) = self.expected.kind(name) else {
            return Ok(Err(FileRefusal::new("file_name", "a name the run does not expect")));
        };
        if bytes.len() > kind.size_cap() {
            let detail = format!("{} bytes, over the cap of {}", bytes.len(), kind.size_cap());
            return Ok(Err(FileRefusal::new("file_size", detail)));
        }
        let cap = if kind == FileKind::Histogram {
            MAX_INCARNATIONS
        } else {
            1
        };
        let taken = self.taken.entry(pattern.clone()).or_default();
        if !taken.contains(name) && taken.len() >= cap {
            let detail = format!("more than {cap} files named {pattern}");
            return Ok(Err(FileRefusal::new("file_count", detail)));
        }
        let dir = self.work_dir.join(QUARANTINE);
        fs::create_dir_all(&dir)?;
        let quarantined = dir.join(name);
        atomic_file::write_atomic(&quarantined, bytes)?;
        if let Err(detail) = kind.check(name, bytes, &self.plans) {
            return Ok(Err(FileRefusal::new("file_content", detail)));
        }
        fs::rename(&quarantined, self.work_dir.join(name))?;
        taken.insert(name.to_string());
        Ok(Ok(()))
    }
}

/// The plans the run's learning agents learn on, by agent, as host A loads
/// them from the run's experiment (empty where it cannot: then value files
/// are checked without their plan).
pub fn expected_plans(info: &RunInfo) -> BTreeMap<usize, Vec<PlanLabels>> {
    let Ok(spec) = serde_json::from_value::<ExperimentSpec>(info.spec.clone()) else {
        return BTreeMap::new();
    };
    let labels = |plan: &learnpnp::Plan| {
        plan.activation_plans()
            .into_iter()
            .map(PlanLabels::of)
            .collect::<Vec<_>>()
    };
    let mut plans = BTreeMap::new();
    match &spec.domain {
        DomainSpec::World { plans: paths, .. } => {
            for &a in &info.remote {
                if let Some(Ok(plan)) = paths
                    .get(a)
                    .map(|p| learnpnp::plan_file::load_plan(p, learnpnp::AllowedAtoms::Open))
                {
                    plans.insert(a, labels(&plan));
                }
            }
        }
        domain => {
            if let Ok(Some(plan)) = domain.load_plan() {
                for &a in &info.remote {
                    plans.insert(a, labels(&plan));
                }
            }
        }
    }
    plans
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipc::wait::WaitStrategy;
    use crate::multiprocess::Clock;

    fn info(roster: Roster, remote: Vec<usize>) -> RunInfo {
        RunInfo {
            prefix: "lpabc_".into(),
            run_id: 7,
            run: 0,
            roster,
            remote,
            clock: Clock::Lockstep,
            wait: WaitStrategy::Yield,
            checkpoint_every: 10,
            floor_round_trips: 100,
            spec: serde_json::Value::Null,
        }
    }

    #[test]
    fn host_b_ships_its_own_agents_files_only() {
        let keepaway = ShippedFiles::of(&info(Roster::Keepaway, vec![2]));
        for name in [
            "values-agent3.bin",
            "compute-keeper3.4242.hdr",
            "floor-remote-host.17.hdr",
            HOST_B_LINK_REPORT,
        ] {
            assert!(keepaway.kind(name).is_some(), "{name}");
        }
        for name in [
            "spec.json",
            "values.bin",
            "values-agent2.bin",
            "compute-keeper1.4242.hdr",
            "compute-keeper3..hdr",
            "compute-keeper3.12x.hdr",
            "run-info.json",
            "",
        ] {
            assert!(keepaway.kind(name).is_none(), "{name}");
        }
        assert_eq!(
            keepaway.kind("compute-keeper3.99.hdr"),
            Some((FileKind::Histogram, "compute-keeper3.*.hdr".to_string()))
        );
        assert_eq!(
            keepaway.kind("values-agent3.bin").map(|k| k.0),
            Some(FileKind::Values(2))
        );
        let world = ShippedFiles::of(&info(Roster::World { agents: 2 }, vec![0]));
        for name in [
            "values.bin",
            "agent1.json",
            "compute-agent1.9.hdr",
            "world-turnaround.9.hdr",
        ] {
            assert!(world.kind(name).is_some(), "{name}");
        }
        assert!(world.kind("agent2.json").is_none());
        assert!(keepaway.key_patterns().contains(&"compute-keeper3.$*.hdr".to_string()));
    }

    #[test]
    fn a_file_must_hold_what_its_name_says() {
        let none = BTreeMap::new();
        let text = b"these are 23 bytes, no!";
        for kind in [
            FileKind::Histogram,
            FileKind::Values(2),
            FileKind::AgentResult,
            FileKind::LinkReport,
        ] {
            assert!(kind.check("x", text, &none).is_err(), "{kind:?}");
        }
        let mut histogram = Latency::new("compute-keeper3");
        histogram.record(std::time::Duration::from_micros(30));
        let bytes = histogram.to_bytes().unwrap();
        assert_eq!(
            FileKind::Histogram.check("compute-keeper3.1.hdr", &bytes, &none),
            Ok(())
        );
        let report = serde_json::to_vec(&LinkReport::default()).unwrap();
        assert_eq!(FileKind::LinkReport.check(HOST_B_LINK_REPORT, &report, &none), Ok(()));
        // A histogram is not a value file.
        assert!(FileKind::Values(2).check("values-agent3.bin", &bytes, &none).is_err());
    }

    fn histogram() -> Vec<u8> {
        let mut histogram = Latency::new("compute-keeper3");
        histogram.record(std::time::Duration::from_micros(30));
        histogram.to_bytes().unwrap()
    }

    #[test]
    fn the_quarantine_takes_good_files_into_the_run_and_keeps_bad_ones_out() {
        let dir = std::env::temp_dir().join(format!("learnpnp-quarantine-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        let mut quarantine = Quarantine::new(&info(Roster::Keepaway, vec![2]), &dir);
        let garbage = b"these are 23 bytes, no!";
        let reason = |r: std::io::Result<Result<(), FileRefusal>>| r.unwrap().err().map(|e| e.reason);
        assert_eq!(reason(quarantine.take("spec.json", garbage)), Some("file_name"));
        assert_eq!(
            reason(quarantine.take("compute-keeper3.1.hdr", garbage)),
            Some("file_content")
        );
        assert!(!dir.join("compute-keeper3.1.hdr").exists());
        assert!(
            dir.join(QUARANTINE).join("compute-keeper3.1.hdr").exists(),
            "kept to be looked at"
        );
        // 64 good histograms of keeper 3, then no more.
        for pid in 1..=MAX_INCARNATIONS {
            assert_eq!(
                reason(quarantine.take(&format!("compute-keeper3.{pid}.hdr"), &histogram())),
                None
            );
        }
        assert_eq!(
            reason(quarantine.take("compute-keeper3.999.hdr", &histogram())),
            Some("file_count")
        );
        // A good file stays when a bad one of its name comes after it.
        assert_eq!(
            reason(quarantine.take("compute-keeper3.1.hdr", garbage)),
            Some("file_content")
        );
        assert_eq!(fs::read(dir.join("compute-keeper3.1.hdr")).unwrap(), histogram());
        let huge = vec![0u8; FileKind::LinkReport.size_cap() + 1];
        assert_eq!(reason(quarantine.take(HOST_B_LINK_REPORT, &huge)), Some("file_size"));
        assert_eq!(quarantine.refused.len(), 5);
        let _ = fs::remove_dir_all(&dir);
    }
}
