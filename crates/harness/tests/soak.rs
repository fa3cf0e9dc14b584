//! Soaks end to end: `learnpnp-soak soak` runs the system (the supervisor,
//! the simulator and the keeper processes on iceoryx2 shared memory) while
//! sampling every process, with and without faults. Each test has its own
//! namespace directory (`LEARNPNP_IPC_DIR`) and checks afterwards that
//! nothing of its runs is left in `/dev/shm` or in that directory, and that
//! no process of its runs is still alive.

use std::fs;
use std::process::{Command, Stdio};

use serde_json::Value;

use crate::support::{Sandbox, prefixes, summary, workspace_binary};
use crate::util::text;

/// The binaries a soak starts beside `learnpnp-soak`, which `cargo test
/// --workspace` builds (the system crate's): checked here, so that the soak
/// never builds them itself.
const RUN_BINARIES: [&str; 2] = ["learnpnp-sim", "learnpnp-agent"];

/// Runs `learnpnp-soak soak` with `args` into `sandbox`'s `out`; returns
/// its `soak.json` and `summary.json` after checking it exited with `code`.
fn soak(sandbox: &Sandbox, out: &str, args: &[&str], code: i32) -> (Value, Value) {
    for binary in RUN_BINARIES {
        workspace_binary(binary);
    }
    let output = Command::new(env!("CARGO_BIN_EXE_learnpnp-soak"))
        .arg("soak")
        .arg("--out")
        .arg(sandbox.out(out))
        .args(args)
        .env("LEARNPNP_IPC_DIR", sandbox.ipc())
        // Under cargo, a missing binary would be built by the soak: never in a test.
        .env_remove("CARGO")
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(code), "{stdout}\n{}", text(&output.stderr));
    assert!(stdout.contains("soak verdict: "), "{stdout}");
    let path = sandbox.out(out).join("soak.json");
    let report: Value = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    (report, summary(&sandbox.out(out)))
}

/// The faults of a chaos soak's report whose description contains `what`.
fn faults<'a>(report: &'a Value, what: &str) -> Vec<&'a Value> {
    report["faults"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["kind"].as_str().unwrap().contains(what))
        .collect()
}

/// A minute of lock-step: memory and descriptors flat after the warm-up,
/// every process sampled every second, nothing left behind. This is the
/// suite's leak and hang detector (the day-long soak is in docs/results/SOAK.md).
#[test]
fn a_minute_of_lockstep_soak_leaks_nothing() {
    let sandbox = Sandbox::new("soak");
    let (report, s) = soak(&sandbox, "soak", &["--duration", "60"], 0);
    assert_eq!(report["passed"], true, "{report}");
    assert!(report["rss_growth_percent"].as_f64().unwrap() < 1.0, "{report}");
    assert!(report["fd_growth"].as_i64().unwrap() <= 0, "{report}");
    assert_eq!(report["restarts"], 0);
    assert_eq!(report["leftover_shm_files"], 0);
    assert!(report["episodes"].as_u64().unwrap() > 0, "{report}");
    assert_eq!(s["scheduling"], "normal", "lock-step is never real-time scheduled");
    let csv = fs::read_to_string(sandbox.out("soak").join("soak.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("seconds,process,pid,rss_kib,anon_kib,open_fds,shm_files,shm_bytes")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    for process in ["supervisor", "simulator", "keeper 1", "keeper 2", "keeper 3"] {
        let samples = rows.iter().filter(|r| r[1] == process).count();
        assert!(samples >= 55, "{process}: {samples} samples in a minute");
    }
    assert!(
        fs::read_to_string(sandbox.out("soak").join("soak.svg"))
            .unwrap()
            .contains("<svg")
    );
    sandbox.assert_clean(&prefixes(&s));
}

/// Every lock-step fault: killed agents and simulator restarted with their
/// values and journal, garbage refused, failed checkpoint writes survived,
/// CPU load beside the run; nothing left in /dev/shm.
#[test]
fn lockstep_chaos_every_fault_is_survived() {
    let sandbox = Sandbox::new("chaos");
    let (report, s) = soak(&sandbox, "chaos", &["--duration", "50", "--chaos", "3"], 0);
    for what in [
        "SIGKILL keeper",
        "SIGKILL simulator",
        "garbage",
        "checkpoint write",
        "CPU load",
    ] {
        let found = faults(&report, what);
        assert!(!found.is_empty(), "no {what} fault: {report}");
        for fault in found {
            assert_eq!(fault["survived"], true, "{fault}");
        }
    }
    for garbage in faults(&report, "garbage") {
        assert!(
            garbage["outcome"].as_str().unwrap().contains("none applied"),
            "{garbage}"
        );
    }
    assert_eq!(report["values_survived"], true, "{report}");
    assert!(report["restarts"].as_u64().unwrap() >= 2, "{report}");
    assert_eq!(report["leftover_shm_files"], 0);
    assert!(report["failure"].is_null(), "{report}");
    assert_eq!(report["passed"], true, "{report}");
    sandbox.assert_clean(&prefixes(&s));
}

/// Real time: an agent stopped for two seconds misses its deadlines (counted),
/// the others go on, and it catches up.
#[test]
fn realtime_chaos_a_stopped_agent_catches_up() {
    let sandbox = Sandbox::new("chaos-rt");
    let (report, s) = soak(
        &sandbox,
        "chaos",
        &["--mode", "realtime", "--duration", "40", "--chaos", "8"],
        0,
    );
    let stopped = faults(&report, "SIGSTOP keeper");
    assert_eq!(stopped.len(), 1, "{report}");
    assert_eq!(stopped[0]["survived"], true, "{}", stopped[0]);
    assert!(report["missed_deadlines"].as_u64().unwrap() > 0, "{report}");
    assert!(
        s["late_cycles"]["simulator"].is_u64(),
        "the simulator's cycle is in the summary: {s}"
    );
    assert!(faults(&report, "").iter().all(|f| f["survived"] == true), "{report}");
    // Only the two kills restarted anything: the stopped agent did not die.
    assert_eq!(report["restarts"], 2, "{report}");
    assert_eq!(report["leftover_shm_files"], 0);
    // The floor is sampled in the cycles of a real-time run, beside the round
    // trips, and the report says how the processes were scheduled.
    assert!(s["floor_us"]["p50"].as_f64().unwrap() > 0.0, "{s}");
    let scheduling = s["scheduling"].as_str().unwrap();
    assert!(
        scheduling == "SCHED_FIFO 10" || scheduling.starts_with("normal (SCHED_FIFO 10 refused: "),
        "{scheduling}"
    );
    sandbox.assert_clean(&prefixes(&s));
}
