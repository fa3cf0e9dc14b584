//! A run with a view: the agents publish their live feed on iceoryx2, the
//! read-only view process (`learnpnp-view`) serves it; the run plays the
//! same episodes as without one, garbage on a feed is refused and counted,
//! and a killed view does not stop the run.

use std::fs;
use std::path::Path;
use std::process::Stdio;
use std::time::Duration;

use learnpnp_system::ipc::feed::feed_service;
use learnpnp_system::multiprocess::supervisor::{IDENTITY_FILE, run_work_dir};
use serde_json::Value;
use shm_layouts::{FeedHeader, PROTOCOL_VERSION};

use crate::multiprocess::{
    Sandbox, assert_same_files, finish, foreign_node, in_process, kill, pids_with_all, prefixes, summary, wait_until,
};
use crate::util::text;

/// A longer run's protocol, for what happens while it runs.
const LONGER: &[&str] = &[
    "--episodes",
    "1000",
    "--eval-every",
    "500",
    "--eval-episodes",
    "3",
    "--greedy-episodes",
    "3",
];

/// The learner and seed of every run here.
const LEARNER: &[&str] = &["--seed", "3", "--algo", "soft-sosmc"];

/// A short lock-step run (its episodes those of `in_process` with the same flags).
const SHORT: &[&str] = &[
    "--seed",
    "3",
    "--algo",
    "soft-sosmc",
    "--episodes",
    "60",
    "--eval-every",
    "30",
    "--eval-episodes",
    "3",
    "--greedy-episodes",
    "3",
];

/// The records of a view's JSON lines, by kind (`Plan`, `Marking`, `Health`, ...).
fn records(path: &Path) -> Vec<(String, Value)> {
    fs::read_to_string(path)
        .unwrap_or_default()
        .lines()
        .filter_map(|line| serde_json::from_str::<Value>(line).ok())
        .filter_map(|v| {
            let (kind, body) = v.as_object()?.iter().next()?;
            Some((kind.clone(), body.clone()))
        })
        .collect()
}

/// The run's prefix and id, once its supervisor has named them.
fn identity(out: &Path) -> (String, u64) {
    let path = || run_work_dir(out, 0).join(IDENTITY_FILE);
    assert!(wait_until(Duration::from_secs(60), || path().exists()));
    let identity: Value = serde_json::from_str(&fs::read_to_string(path()).unwrap()).unwrap();
    (
        identity["ipc_prefix"].as_str().unwrap().to_string(),
        identity["run_id"].as_u64().unwrap(),
    )
}

#[test]
fn a_view_serves_every_process_and_changes_no_episode() {
    let sandbox = Sandbox::new("view");
    let out = sandbox.out("system");
    let jsonl = sandbox.out("feed.jsonl");
    let output = sandbox
        .supervisor("system", SHORT)
        .arg("--view-jsonl")
        .arg(&jsonl)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    in_process(
        "keepaway-position",
        "soft-sosmc",
        "3",
        &SHORT[4..],
        &sandbox.out("inproc"),
    );
    assert_same_files(
        &out,
        &sandbox.out("inproc"),
        &["episodes.csv", "curve.csv", "values.bin"],
    );
    let records = records(&jsonl);
    for process in ["simulator", "keeper 1", "keeper 2", "keeper 3", "view"] {
        assert!(
            records
                .iter()
                .any(|(kind, r)| kind == "Health" && r["process"] == process),
            "no health of {process}"
        );
    }
    let s = summary(&out);
    assert_eq!(s["complete"], true);
    assert_eq!(s["restarts"], 0);
    let view = &s["view"];
    assert_eq!(view["feed"]["rejected"]["content"], 0, "{view}");
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn garbage_on_a_feed_is_refused_and_counted_and_the_view_serves_on() {
    let sandbox = Sandbox::new("view-garbage");
    let out = sandbox.out("system");
    let jsonl = sandbox.out("feed.jsonl");
    let child = sandbox
        .supervisor("system", LEARNER)
        .args(LONGER)
        .arg("--view-jsonl")
        .arg(&jsonl)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (prefix, run_id) = identity(&out);
    // The view subscribes before it serves its first health record.
    let healths = || records(&jsonl).iter().filter(|(kind, _)| kind == "Health").count();
    assert!(wait_until(Duration::from_secs(60), || healths() > 0));
    let garbage = [
        (PROTOCOL_VERSION, 0, run_id, b"\x93\xff\x00 random bytes".to_vec()),
        (PROTOCOL_VERSION + 1, 0, run_id, b"{}".to_vec()),
        (PROTOCOL_VERSION, 0, run_id ^ 1, b"{}".to_vec()),
        (PROTOCOL_VERSION, 2, run_id, b"{}".to_vec()),
        (
            PROTOCOL_VERSION,
            0,
            run_id,
            br#"{"Health":{"process":"x","pid":null,"alive":true,"heartbeat_age_ms":0,"restarts":0,"rejections":0}}"#
                .to_vec(),
        ),
    ];
    {
        let node = foreign_node(&sandbox, &prefix);
        let publisher = feed_service(&node, 0).unwrap().publisher_builder().create().unwrap();
        for (sequence, (version, sender, run_id, bytes)) in garbage.iter().enumerate() {
            let mut sample = publisher.loan_slice_uninit(bytes.len()).unwrap();
            *sample.user_header_mut() = FeedHeader {
                version: *version,
                sender: *sender,
                run_id: *run_id,
                sequence: sequence as u64 + 1,
            };
            assert_eq!(sample.write_from_slice(bytes).send().unwrap(), 1, "the view subscribes");
        }
        std::thread::sleep(Duration::from_millis(300));
    }
    let served = healths();
    assert!(
        wait_until(Duration::from_secs(10), || healths() > served),
        "the view serves on"
    );
    let output = finish(child);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let s = summary(&out);
    let rejected = &s["view"]["feed"]["rejected"];
    assert_eq!(rejected["version"], 1, "{rejected}");
    assert_eq!(rejected["run"], 1, "{rejected}");
    assert_eq!(rejected["sender"], 1, "{rejected}");
    assert_eq!(
        rejected["content"], 2,
        "random bytes, a health record from an agent: {rejected}"
    );
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn a_killed_view_does_not_stop_the_run() {
    let sandbox = Sandbox::new("view-kill");
    let out = sandbox.out("system");
    let jsonl = sandbox.out("feed.jsonl");
    let child = sandbox
        .supervisor("system", LEARNER)
        .args(LONGER)
        .arg("--view-jsonl")
        .arg(&jsonl)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    identity(&out);
    assert!(wait_until(Duration::from_secs(60), || fs::metadata(&jsonl)
        .is_ok_and(|m| m.len() > 0)));
    let work = run_work_dir(&out, 0);
    let views = pids_with_all(&["learnpnp-view", &work.to_string_lossy()]);
    assert_eq!(views.len(), 1, "{views:?}");
    kill(views[0], libc::SIGKILL);
    let output = finish(child);
    assert!(output.status.success(), "{}", text(&output.stderr));
    in_process("keepaway-position", "soft-sosmc", "3", LONGER, &sandbox.out("inproc"));
    assert_same_files(
        &out,
        &sandbox.out("inproc"),
        &["episodes.csv", "curve.csv", "values.bin"],
    );
    let s = summary(&out);
    assert_eq!(s["complete"], true);
    let fault = &s["faults"][0];
    assert!(
        fault["kind"].as_str().unwrap().contains("the view exited: signal 9"),
        "{fault}"
    );
    sandbox.assert_clean(&prefixes(&s));
}
