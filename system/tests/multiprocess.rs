//! The multi-process system end to end: the supervisor, the simulator and the
//! keeper processes on iceoryx2 shared memory. Each test has its own
//! namespace directory (`LEARNPNP_IPC_DIR`) and checks afterwards that nothing
//! of its runs is left in `/dev/shm` or in that directory, and that no
//! process of its runs is still alive.

use crate::support::{
    Sandbox, assert_plays_in_process, assert_same_files, finish, first_episode_event, foreign_node, in_process, kill,
    pids_with, pids_with_all, prefixes, stop, summary, supervisor_binary, wait_until,
};
use crate::util::text;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::Duration;

use iceoryx2::prelude::*;
use learnpnp_harness::garbage::Garbage;
use learnpnp_system::ipc::namespace::Namespace;
use learnpnp_system::multiprocess::host::simulator::JOURNAL_FILE;
use learnpnp_system::multiprocess::supervisor::{IDENTITY_FILE, run_work_dir};
use serde_json::Value;
use shm_layouts::{
    AgentReport, Control, EpisodeEvent, Header, Heartbeat, KeeperCommand, KeeperSnapshot, PROTOCOL_VERSION,
    SENDER_SUPERVISOR, services,
};

const SHORT: &[&str] = &[
    "--episodes",
    "40",
    "--eval-every",
    "20",
    "--eval-episodes",
    "3",
    "--greedy-episodes",
    "3",
];

/// Waits until run 0 of `out` has written its second checkpoint of keeper 1
/// (the run is under way), or panics.
fn wait_for_progress(out: &Path) {
    // The work directory is found anew: it appears when the supervisor starts.
    let prev = || run_work_dir(out, 0).join("values.bin.prev");
    assert!(
        wait_until(Duration::from_secs(120), || prev().exists()),
        "the run made no progress: {} never appeared",
        prev().display()
    );
}

fn lockstep_matches_in_process(domain: &str, algo: &str, values: &[&str]) {
    let sandbox = Sandbox::new(&format!("same-{domain}"));
    let output = sandbox
        .supervisor("system", &["--domain", domain, "--algo", algo, "--seed", "5"])
        .args(SHORT)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    in_process(domain, algo, "5", SHORT, &sandbox.out("inproc"));
    let mut files = vec!["episodes.csv", "curve.csv", "runs.csv"];
    files.extend(values);
    assert_same_files(&sandbox.out("system"), &sandbox.out("inproc"), &files);
    let s = summary(&sandbox.out("system"));
    assert_eq!(s["mode"], "lockstep");
    assert_eq!(s["complete"], true);
    assert_eq!(s["restarts"], 0);
    assert_eq!(s["late_cycles"]["simulator"], 0, "lock-step keeps no cycle");
    assert_eq!(s["leftover_shm_files"], 0);
    assert!(s["latency_us"]["p50"].as_f64().unwrap() > 0.0);
    assert!(s["floor_us"]["p50"].as_f64().unwrap() > 0.0);
    assert!(sandbox.out("system").join("latency/roundtrip.hgrm").exists());
    assert!(sandbox.out("system").join("latency.svg").exists());
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn lockstep_positioning_plays_the_in_process_episodes() {
    lockstep_matches_in_process(
        "keepaway-position",
        "soft-sosmc",
        &["values.bin", "values-agent2.bin", "values-agent3.bin"],
    );
}

#[test]
fn lockstep_pass_decision_plays_the_in_process_episodes() {
    lockstep_matches_in_process("keepaway-pass", "sarsa-lambda", &["values.bin"]);
}

/// Starts the supervisor of a run of `episodes` checkpointing every
/// `checkpoint_every` episodes into `sandbox`'s `system`, its output piped.
fn spawn_run(sandbox: &Sandbox, episodes: &str, checkpoint_every: &str) -> Child {
    sandbox
        .supervisor(
            "system",
            &["--episodes", episodes, "--checkpoint-every", checkpoint_every],
        )
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Starts a run of `episodes` checkpointing every 10 episodes, waits until it
/// is under way, lets `tamper` act on keeper `keeper`'s agent process (its
/// pid) and the run's work directory while the agent is stopped, then kills
/// the agent; returns the supervisor's output, the run's output directory and
/// the work directory as it was during the run.
fn kill_keeper_after(
    sandbox: &Sandbox,
    episodes: &str,
    keeper: usize,
    tamper: impl FnOnce(&Path),
) -> (Output, PathBuf, PathBuf) {
    let out = sandbox.out("system");
    let child = spawn_run(sandbox, episodes, "10");
    wait_for_progress(&out);
    let work = run_work_dir(&out, 0);
    let agents = pids_with_all(&["learnpnp-agent", &work.to_string_lossy(), &format!("--keeper {keeper}")]);
    assert_eq!(agents.len(), 1, "{agents:?}");
    stop(agents[0]);
    tamper(&work);
    kill(agents[0], libc::SIGKILL);
    (finish(child), out, work)
}

#[test]
fn killed_agent_is_restarted_from_its_checkpoint() {
    let sandbox = Sandbox::new("kill-agent");
    let (output, out, _) = kill_keeper_after(&sandbox, "600", 2, |_| {});
    assert!(output.status.success(), "{}", text(&output.stderr));
    let s = summary(&out);
    assert_eq!(s["complete"], true);
    assert_eq!(s["restarts"], 1);
    let fault = &s["faults"][0];
    assert!(
        fault["kind"]
            .as_str()
            .unwrap()
            .contains("keeper 2 exited: signal 9 (SIGKILL)"),
        "{fault}"
    );
    assert!(
        fault["outcome"]
            .as_str()
            .unwrap()
            .contains("restarted from its checkpoint"),
        "{fault}"
    );
    // Unless the kill fell between two episodes, the episode in flight was discarded.
    let aborted = s["aborted"].as_array().unwrap();
    assert!(aborted.len() <= 1, "{aborted:?}");
    for a in aborted {
        assert_eq!(a["keepers"], serde_json::json!([2]));
    }
    assert_eq!(s["aborted_episodes"], aborted.len());
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn killed_simulator_ends_the_run() {
    let sandbox = Sandbox::new("kill-sim");
    let out = sandbox.out("system");
    let child = spawn_run(&sandbox, "2000", "10");
    wait_for_progress(&out);
    let work = run_work_dir(&out, 0);
    let sims = pids_with_all(&["learnpnp-sim", &work.to_string_lossy()]);
    assert_eq!(sims.len(), 1, "{sims:?}");
    kill(sims[0], libc::SIGKILL);
    let output = finish(child);
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    assert!(text(&output.stderr).contains("the simulator exited: signal 9 (SIGKILL)"));
    let s = summary(&out);
    assert_eq!(s["complete"], false);
    assert!(s["failure"].as_str().unwrap().contains("simulator exited"));
    // The agents were stopped with a final checkpoint (published with the results).
    assert!(persist_loads(&run_work_dir(&out, 0).join("values.bin")));
    sandbox.assert_clean(&prefixes(&s));
}

/// The simulator measures the lock-step floor before the first episode; one
/// that outlasts the heartbeat timeout is no hang, and no stall: the simulator
/// beats while it measures. (A loaded machine made one last that long with
/// the default round trips, and the simulator was killed as silent.) Each run
/// sizes its measurement from the previous run's round trips to last about
/// 5 s, until one lasts longer than the 3 s timeout (the round trip varies
/// with the machine's load).
#[test]
fn a_floor_measurement_longer_than_the_heartbeat_timeout_is_not_a_hang() {
    const TIMEOUT_SECONDS: f64 = 3.0;
    let sandbox = Sandbox::new("long-floor");
    // Seconds the floor measurement of `round_trips` took in a run that must succeed.
    let run = |out: &str, round_trips: u64| {
        let output = Command::new(supervisor_binary())
            .arg("--out")
            .arg(sandbox.out(out))
            .args(["--floor-round-trips", &round_trips.to_string()])
            .args(["--heartbeat-timeout", &TIMEOUT_SECONDS.to_string()])
            .args(SHORT)
            .env("LEARNPNP_IPC_DIR", sandbox.ipc())
            .stdin(Stdio::null())
            .output()
            .unwrap();
        let s = summary(&sandbox.out(out));
        assert!(output.status.success(), "{}\n{s}", text(&output.stderr));
        assert_eq!(s["restarts"], 0, "{s}");
        sandbox.assert_clean(&prefixes(&s));
        s["floor_us"]["mean"].as_f64().unwrap() * round_trips as f64 / 1e6
    };
    let mut round_trips = 20_000;
    let mut measuring = run("calibration", round_trips);
    for attempt in 1..=3 {
        round_trips = (5.0 / measuring * round_trips as f64).clamp(20_000.0, 10_000_000.0) as u64;
        measuring = run(&format!("long-{attempt}"), round_trips);
        if measuring > TIMEOUT_SECONDS + 0.5 {
            return;
        }
    }
    panic!("the floor took {measuring:.1} s ({round_trips} round trips): too short to test the timeout");
}

fn persist_loads(path: &Path) -> bool {
    learnpnp::learning::persist::load(path).is_ok()
}

#[test]
fn killed_supervisor_is_cleaned_up_by_the_next_launch() {
    let sandbox = Sandbox::new("kill-supervisor");
    let first = sandbox.out("first");
    let mut child = sandbox
        .supervisor("first", &["--episodes", "2000", "--checkpoint-every", "10"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for_progress(&first);
    let identity: Value =
        serde_json::from_str(&fs::read_to_string(run_work_dir(&first, 0).join(IDENTITY_FILE)).unwrap()).unwrap();
    let stale = identity["ipc_prefix"].as_str().unwrap().to_string();
    kill(child.id() as i32, libc::SIGKILL);
    let _ = child.wait();
    let work = run_work_dir(&first, 0);
    assert!(
        wait_until(Duration::from_secs(5), || pids_with(&work.to_string_lossy()).is_empty()),
        "the children outlived their supervisor"
    );
    let namespace = Namespace::at(&sandbox.ipc(), &stale).unwrap();
    assert!(
        !namespace.files().is_empty(),
        "a SIGKILLed supervisor leaves its namespace"
    );

    let output = sandbox.supervisor("second", SHORT).output().unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains(&format!("iceoryx2 namespace {stale}")),
        "the next launch reports the cleanup: {stderr}"
    );
    let s = summary(&sandbox.out("second"));
    assert!(!prefixes(&s).contains(&stale), "a stale prefix is never reused");
    let mut all = prefixes(&s);
    all.push(stale);
    sandbox.assert_clean(&all);
}

#[test]
fn garbage_on_the_services_is_rejected_and_never_applied() {
    let sandbox = Sandbox::new("garbage");
    let out = sandbox.out("system");
    // The hosts' short protocol without its seed and algorithm.
    let protocol = &crate::support::SHORT[..8];
    let child = sandbox
        .supervisor("system", &["--seed", "7", "--algo", "soft-sosmc"])
        .args(protocol)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let identity_path = || run_work_dir(&out, 0).join(IDENTITY_FILE);
    assert!(wait_until(Duration::from_secs(60), || identity_path().exists()));
    let identity_path = identity_path();
    let identity: Value = serde_json::from_str(&fs::read_to_string(&identity_path).unwrap()).unwrap();
    let prefix = identity["ipc_prefix"].as_str().unwrap().to_string();
    let run_id = identity["run_id"].as_u64().unwrap();
    {
        let node = foreign_node(&sandbox, &prefix);
        // Every process subscribes before its first heartbeat: once all four
        // are heard, the garbage reaches them all (and waits in their queues).
        let heartbeats = node
            .service_builder(&ServiceName::new(services::HEARTBEAT).unwrap())
            .publish_subscribe::<Heartbeat>()
            .open()
            .unwrap()
            .subscriber_builder()
            .create()
            .unwrap();
        let mut heard = std::collections::BTreeSet::new();
        assert!(wait_until(Duration::from_secs(60), || {
            while let Ok(Some(h)) = heartbeats.receive() {
                heard.insert(h.header.sender);
            }
            heard.len() == 4
        }));
        let header = Header::new(0, run_id);
        let command = KeeperCommand {
            header,
            episode: 1,
            cycle_seq: 1,
            kind: 0,
            flags: 0,
            arg0: 0.0,
            arg1: 0.0,
        };
        let mut garbage = Garbage::default();
        garbage.commands[0] = vec![
            KeeperCommand {
                header: Header {
                    version: PROTOCOL_VERSION + 1,
                    ..header
                },
                ..command
            },
            KeeperCommand {
                kind: 2,
                arg0: f64::NAN,
                ..command
            },
            KeeperCommand { kind: 99, ..command },
            KeeperCommand {
                header: Header::new(2, run_id),
                ..command
            },
        ];
        let mut snapshot: KeeperSnapshot = learnpnp_system::multiprocess::host::simulator::floor_ping(run_id, 1);
        snapshot.me = 1;
        snapshot.players[4].pos[0] = f64::NAN;
        garbage.snapshots[1] = vec![snapshot, KeeperSnapshot { me: 7, ..snapshot }];
        let event = first_episode_event(run_id, 77);
        garbage.episode = vec![
            event,
            EpisodeEvent {
                mode: 9,
                kind: 1,
                ..event
            },
        ];
        garbage.reports = vec![AgentReport {
            header: Header::new(5, run_id),
            episode: 1,
            kind: 2,
            pid: 0,
            exploratory: 0,
            reserved: [0; 7],
        }];
        let control = Control {
            header: Header::new(SENDER_SUPERVISOR, run_id),
            command: 42,
            target: u32::MAX,
            sequence: 1,
            pid: 0,
            reserved: 0,
        };
        garbage.control = vec![
            control,
            Control {
                header: Header::new(1, run_id),
                command: 1,
                ..control
            },
        ];
        // Samples live in the publisher's memory: a sample still queued when
        // its publisher goes is lost, and the simulator reads the keepers'
        // command services only once its floor measurement (2000 round trips)
        // is over; so the publishers stay long enough for that on a loaded
        // machine (with 300 ms, under a load average of 17, the garbage on the
        // command services went unread).
        let delivered = garbage.publish(&node, Duration::from_secs(3)).unwrap();
        assert_eq!(delivered.len(), 5, "{delivered:?}");
        for d in &delivered {
            assert!(d.subscribers > 0, "no subscriber on {}", d.service);
        }
    }
    assert_plays_in_process(child, &sandbox, "7", protocol);
    let s = summary(&out);
    let sim = &s["rejected_messages"]["simulator"];
    assert!(sim["version"].as_u64().unwrap() >= 1, "{sim}");
    assert!(
        sim["content"].as_u64().unwrap() >= 3,
        "NaN, an unknown kind, an unknown control: {sim}"
    );
    assert!(
        sim["sender"].as_u64().unwrap() >= 3,
        "keeper 3 on keeper 1's service, report, control: {sim}"
    );
    let keeper2 = &s["rejected_messages"]["keeper 2"];
    assert!(
        keeper2["content"].as_u64().unwrap() >= 4,
        "NaN, another's view, two bad events: {keeper2}"
    );
    for k in ["keeper 1", "keeper 3"] {
        assert!(s["rejected_messages"][k]["content"].as_u64().unwrap() >= 3, "{s}");
    }
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn corrupt_checkpoint_at_restart_resumes_from_the_previous_one() {
    let sandbox = Sandbox::new("corrupt-checkpoint");
    let (output, out, work) = kill_keeper_after(&sandbox, "600", 1, |work| {
        fs::write(work.join("values.bin"), b"LPNPVALS garbage").unwrap();
    });
    let checkpoint = work.join("values.bin");
    assert!(output.status.success(), "{}", text(&output.stderr));
    let log = fs::read_to_string(run_work_dir(&out, 0).join("keeper1.log")).unwrap();
    assert!(
        log.contains(&checkpoint.display().to_string()) && log.contains("resuming from the previous checkpoint"),
        "the restart names the corrupt file: {log}"
    );
    let s = summary(&out);
    assert_eq!(s["complete"], true);
    assert_eq!(s["restarts"], 1);
    assert_eq!(s["resumes"][0]["source"], "previous checkpoint");
    assert_eq!(s["values_survived"], true, "{}", s["resumes"]);
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn missing_checkpoint_at_restart_is_a_clear_error() {
    let sandbox = Sandbox::new("missing-checkpoint");
    let (output, out, work) = kill_keeper_after(&sandbox, "2000", 3, |work| {
        fs::remove_file(work.join("values-agent3.bin")).unwrap();
        // Keeper 3 may not have written a second checkpoint yet.
        let _ = fs::remove_file(work.join("values-agent3.bin.prev"));
    });
    let checkpoint = work.join("values-agent3.bin");
    assert_eq!(output.status.code(), Some(1), "{}", text(&output.stderr));
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("keeper 3") && stderr.contains(&checkpoint.display().to_string()),
        "the error names the keeper and the file: {stderr}"
    );
    let s = summary(&out);
    assert_eq!(s["complete"], false);
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn sigterm_stops_the_run_with_a_final_checkpoint() {
    let sandbox = Sandbox::new("sigterm");
    let out = sandbox.out("system");
    let child = spawn_run(&sandbox, "2000", "1000");
    // The first checkpoint is the starting values; the run is under way once
    // the first episode's events flow (keeper 1 has acted).
    assert!(wait_until(Duration::from_secs(120), || {
        fs::read_to_string(run_work_dir(&out, 0).join("simulator.log")).is_ok()
            && pids_with_all(&["learnpnp-sim", &run_work_dir(&out, 0).to_string_lossy()]).len() == 1
    }));
    let work = run_work_dir(&out, 0);
    // Learning under way, however loaded the machine: a few learning episodes
    // journalled (the agents have ended the earlier ones by then).
    let learned =
        || fs::read_to_string(work.join(JOURNAL_FILE)).map_or(0, |text| text.matches("\"mode\":\"Learn\"").count());
    assert!(
        wait_until(Duration::from_secs(120), || learned() >= 3),
        "no learning episode ended"
    );
    // The checkpoint of the starting values (the next is 1000 episodes away).
    let start = learnpnp::learning::persist::load(&work.join("values.bin")).unwrap();
    // Twice at once, as `timeout` sends it (to the process, then to its
    // group): still one orderly stop, not the second signal's exit at once.
    kill(child.id() as i32, libc::SIGTERM);
    kill(child.id() as i32, libc::SIGTERM);
    let output = finish(child);
    assert_eq!(output.status.code(), Some(143), "{}", text(&output.stderr));
    let s = summary(&out);
    assert_eq!(s["complete"], false);
    assert!(s["failure"].is_null(), "a requested stop is no failure: {s}");
    let work = run_work_dir(&out, 0);
    let last = learnpnp::learning::persist::load(&work.join("values.bin")).unwrap();
    assert_ne!(
        last, start,
        "the final checkpoint holds what was learned since the start"
    );
    sandbox.assert_clean(&prefixes(&s));
}
