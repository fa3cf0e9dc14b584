//! A world in its own process: `learnpnp-supervisor --world-cmd` with the
//! corridor world (`learnpnp-corridor`, each agent walks a corridor of five
//! cells; the best return is -4) and `plans/corridor.pnml`, whose one choice
//! point is forward or back. Learning over shared memory, repeatability, a
//! plan that does not fit, the world and an agent killed, and garbage on the
//! world's services; each test leaves `/dev/shm` as it was.

use std::fs;
use std::path::Path;
use std::process::{Child, Output, Stdio};
use std::time::Duration;

use crate::support::{Sandbox, identity, kill, pids_with_all, prefixes, summary, wait_until};
use crate::util::{shipped_arg, text};
use learnpnp_harness::garbage::Garbage;
use learnpnp_system::ipc::namespace::Namespace;
use learnpnp_system::ipc::services::node;
use learnpnp_system::multiprocess::supervisor::run_work_dir;
use serde_json::Value;

const CORRIDOR: &str = env!("CARGO_BIN_EXE_learnpnp-corridor");

/// The corridor world's arguments, with `episodes` learning episodes.
fn corridor_run(episodes: u64) -> Vec<String> {
    [
        "--world-cmd",
        CORRIDOR,
        "--plan",
        &shipped_arg("corridor.pnml"),
        "--algo",
        "q-learning",
        "--episodes",
        &episodes.to_string(),
        "--eval-every",
        &episodes.min(100).to_string(),
        "--eval-episodes",
        "0",
        "--greedy-episodes",
        "5",
    ]
    .map(str::to_string)
    .to_vec()
}

fn run(sandbox: &Sandbox, out: &str, args: &[String]) -> Output {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    sandbox.supervisor(out, &args).output().unwrap()
}

fn greedy(summary: &Value) -> f64 {
    summary["experiment"]["final_greedy_mean"].as_f64().unwrap()
}

#[test]
fn the_corridor_is_learned_over_shared_memory_and_a_seed_repeats_its_episodes() {
    let sandbox = Sandbox::new("world-learns");
    let mut used = Vec::new();
    for seed in ["1", "2", "3"] {
        let mut args = corridor_run(150);
        args.extend(["--seed".to_string(), seed.to_string()]);
        let output = run(&sandbox, &format!("seed{seed}"), &args);
        assert!(output.status.success(), "{}", text(&output.stderr));
        let s = summary(&sandbox.out(&format!("seed{seed}")));
        assert_eq!(s["complete"], true, "{s}");
        assert_eq!(greedy(&s), -4.0, "seed {seed}: the greedy walk goes straight forward");
        assert!(s["latency_us"]["p50"].as_f64().unwrap() > 0.0);
        assert!(s["floor_us"]["p50"].as_f64().unwrap() > 0.0);
        // The corridor's step is a small part of a cycle's round trip.
        assert_eq!(s["late_cycles"]["world"], 0, "lock-step keeps no cycle: {s}");
        let turnaround = s["world_turnaround_us"]["p50"].as_f64().unwrap();
        assert!(
            turnaround > 0.0 && turnaround < s["latency_us"]["p50"].as_f64().unwrap(),
            "{s}"
        );
        used.extend(prefixes(&s));
    }
    let mut args = corridor_run(150);
    args.extend(["--seed".to_string(), "1".to_string()]);
    let output = run(&sandbox, "again", &args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    used.extend(prefixes(&summary(&sandbox.out("again"))));
    let episodes = |out: &str| fs::read_to_string(sandbox.out(out).join("episodes.csv")).unwrap();
    assert_eq!(
        episodes("seed1"),
        episodes("again"),
        "the same seed plays the same episodes"
    );
    assert_ne!(episodes("seed1"), episodes("seed2"));
    sandbox.assert_clean(&used);
}

#[test]
fn two_agents_learn_in_one_world_each_with_its_own_values() {
    let sandbox = Sandbox::new("world-agents");
    let mut args = corridor_run(150);
    args.extend(["--agents".to_string(), "2".to_string()]);
    let output = run(&sandbox, "two", &args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let out = sandbox.out("two");
    let s = summary(&out);
    assert_eq!(s["complete"], true, "{s}");
    assert_eq!(greedy(&s), -4.0);
    for file in ["values.bin", "values-agent2.bin"] {
        assert!(run_work_dir(&out, 0).join(file).exists(), "{file}");
    }
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn a_plan_naming_what_the_world_lacks_is_refused_before_any_episode() {
    let sandbox = Sandbox::new("world-misfit");
    let mut args = corridor_run(100);
    args[3] = shipped_arg("sutton.pnml");
    let output = run(&sandbox, "misfit", &args);
    assert!(!output.status.success());
    let s = summary(&sandbox.out("misfit"));
    let failure = s["failure"].as_str().unwrap();
    assert!(
        failure.contains("does not fit the world") && failure.contains("the world's atoms: at_end"),
        "{failure}"
    );
    assert_eq!(s["episodes_played"], 0, "{s}");
    let mut used = prefixes(&s);
    // Each agent its own plan: agent 1's fits, agent 2's does not.
    let mut args = corridor_run(100);
    args.splice(
        2..4,
        [
            "--agent-plan".to_string(),
            shipped_arg("corridor.pnml"),
            "--agent-plan".to_string(),
            shipped_arg("sutton.pnml"),
        ],
    );
    let output = run(&sandbox, "second", &args);
    assert!(!output.status.success());
    let s = summary(&sandbox.out("second"));
    let failure = s["failure"].as_str().unwrap();
    assert!(
        failure.contains("agent 2 exited") && failure.contains("does not fit the world"),
        "{failure}"
    );
    used.extend(prefixes(&s));
    sandbox.assert_clean(&used);
}

/// The process of the world of the run whose namespace is `prefix`: the one
/// whose environment names it and whose command line is the corridor's.
fn world_pid(prefix: &str) -> Option<i32> {
    pids_with_all(&[CORRIDOR]).into_iter().find(|pid| {
        fs::read(format!("/proc/{pid}/environ"))
            .map(|env| text(&env).contains(&format!("LEARNPNP_IPC_PREFIX={prefix}")))
            .unwrap_or(false)
    })
}

/// Waits until agent 1 has journaled `episodes` whole episodes.
fn wait_for_episodes(out: &Path, episodes: usize) {
    let journal = || run_work_dir(out, 0).join("agent1.journal");
    assert!(
        wait_until(Duration::from_secs(120), || fs::read_to_string(journal())
            .is_ok_and(|t| t.lines().count() >= episodes)),
        "the run made no progress"
    );
}

fn spawn(sandbox: &Sandbox, out: &str, args: &[String]) -> Child {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    sandbox
        .supervisor(out, &args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

#[test]
fn a_killed_world_is_restarted_and_the_agent_keeps_learning() {
    let sandbox = Sandbox::new("world-killed");
    let child = spawn(&sandbox, "killed", &corridor_run(3000));
    let out = sandbox.out("killed");
    let (prefix, _) = identity(&out);
    wait_for_episodes(&out, 100);
    let pid = world_pid(&prefix).expect("the world process");
    kill(pid, libc::SIGKILL);
    let output = child.wait_with_output().unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    let s = summary(&out);
    assert_eq!(s["complete"], true, "{s}");
    assert!(s["restarts"].as_u64().unwrap() >= 1, "{s}");
    let faults = s["faults"].to_string();
    assert!(faults.contains("the world exited"), "{faults}");
    assert_eq!(greedy(&s), -4.0);
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn a_killed_agent_resumes_from_its_checkpoint() {
    let sandbox = Sandbox::new("world-agent-killed");
    let mut args = corridor_run(3000);
    args.extend(["--checkpoint-every".to_string(), "50".to_string()]);
    let child = spawn(&sandbox, "agent", &args);
    let out = sandbox.out("agent");
    identity(&out);
    wait_for_episodes(&out, 200);
    // The agent's work directory is in the sandbox (the result set's staging directory).
    let root = out.parent().unwrap().display().to_string();
    let pids = pids_with_all(&["--world-agent", &root]);
    assert_eq!(pids.len(), 1, "{pids:?}");
    kill(pids[0], libc::SIGKILL);
    let output = child.wait_with_output().unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    let s = summary(&out);
    assert_eq!(s["complete"], true, "{s}");
    assert_eq!(s["values_survived"], true, "{s}");
    assert_eq!(s["resumes"].as_array().unwrap().len(), 1, "{s}");
    assert_eq!(greedy(&s), -4.0);
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn garbage_on_the_world_services_is_refused_and_counted() {
    let sandbox = Sandbox::new("world-garbage");
    let child = spawn(&sandbox, "garbage", &corridor_run(4000));
    let out = sandbox.out("garbage");
    let (prefix, run_id) = identity(&out);
    wait_for_episodes(&out, 100);
    let namespace = Namespace::at(&sandbox.ipc(), &prefix).unwrap();
    let foreign = node(&namespace, "foreign").unwrap();
    Garbage::every_world_kind(run_id, 1)
        .publish(&foreign, Duration::from_millis(500))
        .unwrap();
    drop(foreign);
    let output = child.wait_with_output().unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    let s = summary(&out);
    assert_eq!(s["complete"], true, "{s}");
    assert_eq!(greedy(&s), -4.0, "no refused message was applied");
    let agent = &s["rejected_messages"]["agent 1"];
    assert_eq!(
        [&agent["run"], &agent["sender"], &agent["content"], &agent["sequence"]],
        [1, 1, 3, 1],
        "{agent}"
    );
    let world = &s["rejected_messages"]["world"];
    assert_eq!(
        [&world["run"], &world["sender"], &world["content"]],
        [1, 1, 2],
        "{world}"
    );
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn a_world_that_keeps_dying_stops_the_run_with_a_clear_failure() {
    let sandbox = Sandbox::new("world-dying");
    let mut args = corridor_run(100);
    // Each death leaves another last line: the world is restarted up to the limit.
    args[1] = "sh -c 'date +%s%N >&2; exit 3'".to_string();
    args.extend(["--max-restarts".to_string(), "2".to_string()]);
    let output = run(&sandbox, "dying", &args);
    assert!(!output.status.success());
    let s = summary(&sandbox.out("dying"));
    let failure = s["failure"].as_str().unwrap();
    assert!(
        failure.contains("the world exited: exit code 3") && failure.contains("run given up"),
        "{failure}"
    );
    assert_eq!(s["restarts"], 3, "{s}");
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn a_world_that_fails_the_same_way_at_its_start_is_given_up_at_its_second_failure() {
    let sandbox = Sandbox::new("world-failing");
    let mut args = corridor_run(100);
    args[1] = "sh -c 'echo Traceback >&2; echo ValueError: the reward is NaN >&2; exit 1'".to_string();
    let output = run(&sandbox, "failing", &args);
    assert!(!output.status.success());
    let s = summary(&sandbox.out("failing"));
    let failure = s["failure"].as_str().unwrap();
    assert!(
        failure.contains("the world exited: exit code 1, the same way twice before its first episode")
            && failure.contains("(ValueError: the reward is NaN)"),
        "{failure}"
    );
    assert_eq!(s["restarts"], 1, "restarted once, not up to the limit: {s}");
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn in_real_time_the_world_keeps_its_clock_and_counts_the_commands_that_miss_it() {
    let sandbox = Sandbox::new("world-realtime");
    let mut args = corridor_run(4);
    args.extend(["--mode".to_string(), "realtime".to_string()]);
    let child = spawn(&sandbox, "realtime", &args);
    let out = sandbox.out("realtime");
    identity(&out);
    let root = out.parent().unwrap().display().to_string();
    let agent = || pids_with_all(&["--world-agent", &root]);
    assert!(wait_until(Duration::from_secs(30), || agent().len() == 1));
    std::thread::sleep(Duration::from_millis(1000));
    let pid = agent()[0];
    kill(pid, libc::SIGSTOP);
    std::thread::sleep(Duration::from_millis(600));
    kill(pid, libc::SIGCONT);
    let output = child.wait_with_output().unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    let s = summary(&out);
    assert_eq!(s["complete"], true, "{s}");
    let missed = s["missed_deadlines"].as_u64().unwrap();
    assert!(
        missed >= 4,
        "an agent stopped for 600 ms misses about 6 cycles of 100 ms: {missed}"
    );
    assert!(
        s["floor_us"]["p50"].as_f64().unwrap() > 0.0,
        "the floor is sampled beside the run"
    );
    sandbox.assert_clean(&prefixes(&s));
}

/// The heartbeat timeout of the long real-time run (the supervisor's least).
const SHORT_HEARTBEAT_TIMEOUT_S: u64 = 3;

#[test]
fn in_real_time_a_world_heartbeats_through_its_cycles_and_lives_through_many_heartbeat_timeouts() {
    let sandbox = Sandbox::new("world-realtime-long");
    let period_ms = 50;
    let mut args = corridor_run(40);
    args.extend(
        [
            "--mode",
            "realtime",
            "--world-period-ms",
            &period_ms.to_string(),
            "--heartbeat-timeout",
            &SHORT_HEARTBEAT_TIMEOUT_S.to_string(),
        ]
        .map(str::to_string),
    );
    let output = run(&sandbox, "long", &args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let out = sandbox.out("long");
    let s = summary(&out);
    assert_eq!(s["complete"], true, "{s}");
    assert_eq!(s["restarts"], 0, "no process was taken as silent: {s}");
    assert_eq!(s["faults"].as_array().map_or(0, Vec::len), 0, "{s}");
    // The world's last line: the cycles it kept on its clock. Cycles on a
    // grid of 50 ms cannot outnumber the run's time: these many make the run
    // longer than three heartbeat timeouts.
    let log = fs::read_to_string(run_work_dir(&out, 0).join("world.log")).unwrap();
    let line = log
        .lines()
        .rev()
        .find(|l| l.starts_with("world: real time: "))
        .unwrap_or_else(|| panic!("the world says the cycle it kept: {log}"));
    let cycles: u64 = line["world: real time: ".len()..]
        .split(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    let needed = 3 * SHORT_HEARTBEAT_TIMEOUT_S * 1000 / period_ms;
    assert!(cycles > needed, "{cycles} cycles of {period_ms} ms: {line}");
    // Its late cycles reach the summary through its heartbeat.
    let late: u64 = line
        .rsplit(", ")
        .next()
        .and_then(|l| l.strip_suffix(" late"))
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert_eq!(s["late_cycles"]["world"], late, "{line}: {s}");
    sandbox.assert_clean(&prefixes(&s));
}

/// A world whose step waits for its robot longer than the heartbeat timeout
/// keeps house while it waits (as a ROS 2 world does): it is not taken as
/// silent, and the stalled cycle is late (counted, into the summary). The
/// same step blocked without keeping house is a hang: the world is killed.
#[test]
fn a_step_waiting_longer_than_the_heartbeat_timeout_keeps_the_world_alive_and_a_hang_is_killed() {
    let sandbox = Sandbox::new("world-stall");
    let block_ms = SHORT_HEARTBEAT_TIMEOUT_S * 1000 * 3 / 2;
    let timeout = SHORT_HEARTBEAT_TIMEOUT_S.to_string();
    let mut args = corridor_run(5);
    args[1] = format!("{CORRIDOR} --stall-ms {block_ms}");
    args.extend(
        [
            "--mode",
            "realtime",
            "--world-period-ms",
            "50",
            "--heartbeat-timeout",
            &timeout,
        ]
        .map(str::to_string),
    );
    let output = run(&sandbox, "stall", &args);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let s = summary(&sandbox.out("stall"));
    assert_eq!(s["complete"], true, "{s}");
    assert_eq!(s["restarts"], 0, "the stalled world was not taken as silent: {s}");
    assert!(s["late_cycles"]["world"].as_u64().unwrap() >= 1, "{s}");
    let mut used = prefixes(&s);
    let mut args = corridor_run(5);
    args[1] = format!("{CORRIDOR} --hang-ms {block_ms}");
    args.extend(["--heartbeat-timeout", &timeout, "--max-restarts", "0"].map(str::to_string));
    let output = run(&sandbox, "hang", &args);
    assert!(!output.status.success());
    let s = summary(&sandbox.out("hang"));
    let failure = s["failure"].as_str().unwrap();
    assert!(
        failure.contains(&format!("world silent for {timeout} s: killed")),
        "{failure}"
    );
    used.extend(prefixes(&s));
    sandbox.assert_clean(&used);
}

#[test]
fn a_world_whose_program_does_not_exist_is_an_error_naming_it() {
    let sandbox = Sandbox::new("world-missing");
    let mut args = corridor_run(5);
    args[1] = "/nonexistent/learnpnp-ros2-world".to_string();
    let output = run(&sandbox, "missing", &args);
    assert!(!output.status.success());
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("/nonexistent/learnpnp-ros2-world does not exist")
            && stderr.contains("cargo build --release --bin learnpnp-ros2-world"),
        "{stderr}"
    );
}

#[test]
fn a_world_run_by_a_shell_dies_with_a_killed_supervisor_and_the_next_launch_cleans_up() {
    let sandbox = Sandbox::new("world-orphan");
    let mut args = corridor_run(100_000);
    // Run by `sh -c` (the `&&`): the world is the shell's child, not the supervisor's.
    args[1] = format!("{CORRIDOR} && true");
    let mut child = spawn(&sandbox, "first", &args);
    let out = sandbox.out("first");
    let (stale, _) = identity(&out);
    wait_for_episodes(&out, 100);
    assert!(world_pid(&stale).is_some());
    kill(child.id() as i32, libc::SIGKILL);
    let _ = child.wait();
    assert!(
        wait_until(Duration::from_secs(5), || world_pid(&stale).is_none()),
        "the world outlived its supervisor"
    );
    let output = run(&sandbox, "second", &corridor_run(50));
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(
        text(&output.stderr).contains(&format!("iceoryx2 namespace {stale}")),
        "the next launch removes what the killed run left"
    );
    let mut used = prefixes(&summary(&sandbox.out("second")));
    used.push(stale);
    sandbox.assert_clean(&used);
}
