//! A run across two hosts: host A runs the simulator or world, its
//! supervisor, its agents and its bridge; host B runs a remote agent under
//! `learnpnp-supervisor remote`, whose bridge joins host A's over Zenoh
//! (TLS with mutual authentication, the certificates made by
//! `learnpnp-supervisor link-certs` when the test runs).
//! The hosts are two network namespaces this test creates, joined by a veth
//! pair with addresses from 198.18.0.0/15 and nothing else (removed after
//! the test, also when it fails); where namespaces cannot be made (not
//! root), the test says so and runs both hosts on loopback endpoints.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Duration;

use crate::support::{
    SHORT, Sandbox, kill, pids_with_all, prefixes, summary, supervisor_binary, wait_until, workspace_binary,
};
use crate::util::{shipped_arg, text};
use serde_json::Value;

/// Two hosts: network namespaces joined by a veth pair, or loopback.
pub(crate) struct Hosts {
    /// The namespaces (A, B), if they could be made.
    namespaces: Option<(String, String)>,
    /// The veth ends (A's, B's).
    links: (String, String),
    /// Host A's address.
    a: String,
    /// The port host A's bridge listens on.
    port: u16,
}

static HOSTS: AtomicU32 = AtomicU32::new(0);

fn ip(args: &[&str]) -> bool {
    Command::new("ip")
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Checks that the supervisor will start this package's bridge: it looks for
/// it beside itself, in `target/<profile>/`, where cargo built both.
fn assert_bridge_beside_supervisor() {
    let bridge = Path::new(env!("CARGO_BIN_EXE_learnpnp-bridge"));
    let beside = supervisor_binary().with_file_name("learnpnp-bridge");
    assert_eq!(
        bridge, beside,
        "the supervisor starts the bridge beside itself, not the one cargo built for this test"
    );
}

impl Hosts {
    /// Two namespaces joined by a veth pair 198.18.N.1 <-> 198.18.N.2, or
    /// loopback if they cannot be made.
    pub(crate) fn new() -> Self {
        assert_bridge_beside_supervisor();
        let n = HOSTS.fetch_add(1, Ordering::Relaxed);
        let tag = format!("{}{n}", std::process::id() % 100_000);
        let (na, nb) = (format!("lpa{tag}"), format!("lpb{tag}"));
        let (la, lb) = (format!("lva{tag}"), format!("lvb{tag}"));
        let subnet = 1 + (std::process::id() + n) % 250;
        let (a, b) = (format!("198.18.{subnet}.1"), format!("198.18.{subnet}.2"));
        let port = 17000 + (std::process::id() % 1000) as u16 * 10 + n as u16;
        let made = ip(&["netns", "add", &na])
            && ip(&["netns", "add", &nb])
            && ip(&["link", "add", &la, "type", "veth", "peer", "name", &lb])
            && ip(&["link", "set", &la, "netns", &na])
            && ip(&["link", "set", &lb, "netns", &nb])
            && ip(&["-n", &na, "addr", "add", &format!("{a}/30"), "dev", &la])
            && ip(&["-n", &nb, "addr", "add", &format!("{b}/30"), "dev", &lb])
            && ip(&["-n", &na, "link", "set", &la, "up"])
            && ip(&["-n", &nb, "link", "set", &lb, "up"])
            && ip(&["-n", &na, "link", "set", "lo", "up"])
            && ip(&["-n", &nb, "link", "set", "lo", "up"]);
        if made {
            return Hosts {
                namespaces: Some((na, nb)),
                links: (la, lb),
                a,
                port,
            };
        }
        let _ = (ip(&["netns", "del", &na]), ip(&["netns", "del", &nb]));
        eprintln!("note: network namespaces cannot be made here (not root?): both hosts run on loopback endpoints");
        Hosts {
            namespaces: None,
            links: (la, lb),
            a: "127.0.0.1".into(),
            port,
        }
    }

    /// Host A's bridge's endpoint.
    pub(crate) fn endpoint(&self) -> String {
        format!("quic/{}:{}", self.a, self.port)
    }

    /// Makes the run's certificates in `dir` (host A's named by its address).
    pub(crate) fn certs(&self, dir: &Path) -> Certs {
        let made = Command::new(supervisor_binary())
            .args(["link-certs", "--host-a", &self.a, "--dir"])
            .arg(dir)
            .output()
            .unwrap();
        assert!(made.status.success(), "{}", text(&made.stderr));
        Certs {
            host_a: dir.join("host-a").display().to_string(),
            host_b: dir.join("host-b").display().to_string(),
        }
    }

    /// `command` run on host A (`true`) or host B.
    pub(crate) fn on(&self, host_a: bool, command: Command) -> Command {
        let Some((na, nb)) = &self.namespaces else {
            return command;
        };
        let mut wrapped = Command::new("ip");
        wrapped
            .args(["netns", "exec", if host_a { na } else { nb }])
            .arg(command.get_program())
            .args(command.get_args());
        for (key, value) in command.get_envs() {
            if let Some(value) = value {
                wrapped.env(key, value);
            }
        }
        wrapped
    }

    /// Cuts the link (host A's end down) for `outage`, then restores it.
    fn cut_link(&self, outage: Duration) -> bool {
        let Some((na, _)) = &self.namespaces else {
            return false;
        };
        let down = ip(&["-n", na, "link", "set", &self.links.0, "down"]);
        std::thread::sleep(outage);
        down && ip(&["-n", na, "link", "set", &self.links.0, "up"])
    }
}

impl Drop for Hosts {
    fn drop(&mut self) {
        if let Some((na, nb)) = &self.namespaces {
            // Deleting a namespace deletes the veth end in it, and its pair.
            let _ = (ip(&["netns", "del", na]), ip(&["netns", "del", nb]));
        }
    }
}

/// The directories of host A's and host B's certificates.
pub(crate) struct Certs {
    pub(crate) host_a: String,
    pub(crate) host_b: String,
}

/// Host B's supervisor, joining host A's run at `endpoint` with host B's
/// certificates, its files in `out`.
pub(crate) fn remote(sandbox: &Sandbox, out: &Path, endpoint: &str, certs: &Certs) -> Command {
    let mut command = Command::new(supervisor_binary());
    command
        .args([
            "remote",
            "--bridge-connect",
            endpoint,
            "--link-certs",
            &certs.host_b,
            "--out",
        ])
        .arg(out)
        .env("LEARNPNP_IPC_DIR", sandbox.ipc())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    command
}

/// Host A's supervisor with `args`, its results in `out`.
pub(crate) fn host_a(hosts: &Hosts, sandbox: &Sandbox, out: &str, args: &[&str]) -> Child {
    hosts
        .on(true, sandbox.supervisor(out, args))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

pub(crate) fn finished(child: Child) -> Output {
    let output = child.wait_with_output().unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    output
}

/// Host B's summary (the host's own prefix, faults and shipping).
pub(crate) fn remote_summary(out: &Path) -> Value {
    serde_json::from_str(&fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// Host A's arguments for [`SHORT`] with keeper 3 on host B, whose bridge
/// connects to `endpoint` (host A's certificates in `certs`).
pub(crate) fn keeper_3_remote<'a>(endpoint: &'a str, certs: &'a Certs) -> Vec<&'a str> {
    let mut args = SHORT.to_vec();
    args.extend([
        "--remote-agents",
        "3",
        "--bridge-listen",
        endpoint,
        "--link-certs",
        &certs.host_a,
    ]);
    args
}

#[test]
fn a_keeper_on_another_host_plays_exactly_the_one_host_episodes() {
    let sandbox = Sandbox::new("hosts-lockstep");
    let hosts = Hosts::new();
    let one = sandbox.supervisor("one", &SHORT).output().unwrap();
    assert!(one.status.success(), "{}", text(&one.stderr));
    let endpoint = hosts.endpoint();
    let certs = hosts.certs(&sandbox.out("certs"));
    let a_args = keeper_3_remote(&endpoint, &certs);
    let host_a = host_a(&hosts, &sandbox, "two", &a_args);
    let b_out: PathBuf = sandbox.out("host-b");
    let host_b = hosts
        .on(false, remote(&sandbox, &b_out, &endpoint, &certs))
        .spawn()
        .unwrap();
    finished(host_b);
    finished(host_a);
    let episodes = |out: &str| fs::read(sandbox.out(out).join("episodes.csv")).unwrap();
    assert_eq!(episodes("one"), episodes("two"), "the episodes of the one-host run");
    for file in ["values.bin", "values-agent2.bin", "values-agent3.bin"] {
        assert_eq!(
            fs::read(sandbox.out("one").join(file)).unwrap(),
            fs::read(sandbox.out("two").join(file)).unwrap(),
            "{file}: keeper 3's values came back from host B"
        );
    }
    let (a, b) = (summary(&sandbox.out("two")), remote_summary(&b_out));
    assert_eq!(b["shipped"], true, "{b}");
    // Over mutual TLS, with nothing refused and no fault.
    for link in [&a["link"], &b["link"]] {
        assert_eq!(link["security"], "mutual-tls-quic", "{link}");
        assert!(link["refused"].as_object().unwrap().values().all(|n| n == 0), "{link}");
    }
    assert_eq!(a["faults"], serde_json::json!([]), "{a}");
    // The report shows the round trip across the link: keeper 3's own,
    // through both bridges, slower than local keeper 1's.
    let p50 = |k: &str| a["keeper_latency_us"][k]["p50"].as_f64().unwrap();
    assert!(p50("keeper 3") > p50("keeper 1"), "{}", a["keeper_latency_us"]);
    // And each host's floor: host B's measured there, before keeper 3 started.
    for floor in ["floor_us", "remote_host_floor_us"] {
        assert!(a[floor]["p50"].as_f64().is_some_and(|p| p > 0.0), "{floor}: {a}");
    }
    assert_eq!(b["run_prefix"].as_str(), prefixes(&a).first().map(String::as_str));
    assert!(
        fs::read_dir(sandbox.out("two").join("runs/run-0"))
            .unwrap()
            .flatten()
            .any(|e| e.file_name().to_string_lossy().starts_with("compute-keeper3.")),
        "host B's histograms are in host A's report"
    );
    let mut used = prefixes(&summary(&sandbox.out("one")));
    used.extend(prefixes(&a));
    used.push(b["ipc_prefix"].as_str().unwrap().to_string());
    sandbox.assert_clean(&used);
}

/// The corridor world, agent 1 on host B, in real time at 20 ms a cycle.
fn realtime_world(episodes: &str) -> Vec<String> {
    let corridor = workspace_binary("learnpnp-corridor").display().to_string();
    [
        "--world-cmd",
        &corridor,
        "--plan",
        &shipped_arg("corridor.pnml"),
        "--algo",
        "q-learning",
        "--episodes",
        episodes,
        "--eval-every",
        episodes,
        "--eval-episodes",
        "0",
        "--greedy-episodes",
        "2",
        "--mode",
        "realtime",
        "--world-period-ms",
        "20",
        "--remote-agents",
        "1",
    ]
    .map(str::to_string)
    .to_vec()
}

#[test]
fn in_real_time_a_cut_link_and_a_killed_bridge_cost_deadlines_not_the_run() {
    let sandbox = Sandbox::new("hosts-realtime");
    let hosts = Hosts::new();
    let endpoint = hosts.endpoint();
    let certs = hosts.certs(&sandbox.out("certs"));
    let mut a_args = realtime_world("150");
    a_args.extend([
        "--bridge-listen".to_string(),
        endpoint.clone(),
        "--link-certs".into(),
        certs.host_a.clone(),
    ]);
    let a_args: Vec<&str> = a_args.iter().map(String::as_str).collect();
    let host_a = host_a(&hosts, &sandbox, "a", &a_args);
    let b_out = sandbox.out("host-b");
    let host_b = hosts
        .on(false, remote(&sandbox, &b_out, &endpoint, &certs))
        .spawn()
        .unwrap();
    // Once the agent acts, cut the link for two seconds, then kill host A's bridge.
    let journal = b_out.join("agent1.journal");
    assert!(wait_until(Duration::from_secs(60), || fs::read_to_string(&journal)
        .is_ok_and(|t| t.lines().count() >= 2)));
    let cut = hosts.cut_link(Duration::from_secs(2));
    std::thread::sleep(Duration::from_millis(500));
    let root = sandbox.out("a").parent().unwrap().display().to_string();
    let bridges = pids_with_all(&["learnpnp-bridge", "--side host", &root]);
    assert_eq!(bridges.len(), 1, "{bridges:?}");
    kill(bridges[0], libc::SIGKILL);
    finished(host_b);
    finished(host_a);
    let a = summary(&sandbox.out("a"));
    assert_eq!(a["complete"], true, "{a}");
    let missed = a["missed_deadlines"].as_u64().unwrap();
    assert!(missed >= 5, "the outages cost deadlines: {missed}");
    let faults = a["faults"].to_string();
    assert!(faults.contains("the bridge exited"), "{faults}");
    if cut {
        eprintln!("the link was cut for 2 s and the bridge killed: {missed} missed deadlines, the run went on");
    }
    let b = remote_summary(&b_out);
    assert_eq!(b["shipped"], true, "{b}");
    let mut used = prefixes(&a);
    used.push(b["ipc_prefix"].as_str().unwrap().to_string());
    sandbox.assert_clean(&used);
}

/// A 400-episode lock-step Keepaway run with keeper 3 on host B (host A's
/// results in `a`, host B's in `host-b`; `more` arguments for host A),
/// returned once keeper 3 has checkpointed twice on host B.
fn keeper_3_on_host_b(sandbox: &Sandbox, hosts: &Hosts, more: &[&str]) -> (Child, Child, PathBuf) {
    let endpoint = hosts.endpoint();
    let certs = hosts.certs(&sandbox.out("certs"));
    let mut a_args = keeper_3_remote(&endpoint, &certs);
    a_args[1] = "400";
    a_args.extend(["--checkpoint-every", "10"]);
    a_args.extend(more);
    let host_a = host_a(hosts, sandbox, "a", &a_args);
    let b_out = sandbox.out("host-b");
    let host_b = hosts
        .on(false, remote(sandbox, &b_out, &endpoint, &certs))
        .spawn()
        .unwrap();
    let prev = b_out.join("values-agent3.bin.prev");
    assert!(
        wait_until(Duration::from_secs(120), || prev.exists()),
        "no progress on host B"
    );
    (host_a, host_b, b_out)
}

#[test]
fn a_keeper_killed_on_host_b_is_restarted_there_and_host_a_plays_on() {
    let sandbox = Sandbox::new("hosts-restart");
    let hosts = Hosts::new();
    // Once keeper 3 has checkpointed twice on host B, kill it there. Its
    // checkpoints are taken between two episodes: the kill waits a while, so
    // that it most likely lands in an episode (which host A then drops)
    // rather than in the gap between two.
    let (host_a, host_b, b_out) = keeper_3_on_host_b(&sandbox, &hosts, &[]);
    std::thread::sleep(Duration::from_millis(150));
    let keeper = pids_with_all(&["--keeper 3", &b_out.display().to_string()]);
    assert_eq!(keeper.len(), 1, "{keeper:?}");
    kill(keeper[0], libc::SIGKILL);
    finished(host_b);
    finished(host_a);
    let (a, b) = (summary(&sandbox.out("a")), remote_summary(&b_out));
    assert_eq!(a["complete"], true, "{a}");
    // Unless the kill fell between two episodes (the keeper's end-of-episode
    // report and checkpoint are in flight over the link then), host A dropped
    // the episode in flight, and only that one.
    let aborted = a["aborted"].as_array().unwrap();
    assert!(aborted.len() <= 1, "{aborted:?}");
    for episode in aborted {
        assert_eq!(episode["keepers"], serde_json::json!([3]), "{a}");
    }
    assert_eq!(a["aborted_episodes"], aborted.len());
    assert_eq!(b["restarts"], 1, "{b}");
    assert_eq!(b["shipped"], true, "{b}");
    let mut used = prefixes(&a);
    used.push(b["ipc_prefix"].as_str().unwrap().to_string());
    sandbox.assert_clean(&used);
}

#[test]
fn in_lock_step_a_killed_bridge_costs_no_value_and_a_stall_stops_the_run_cleanly() {
    let sandbox = Sandbox::new("hosts-stall");
    let hosts = Hosts::new();
    // Heartbeat timeout 3 s: a lock-step run that stops moving is stopped
    // after 3 x 3 s. Once keeper 3 has checkpointed twice on host B, kill host
    // A's bridge in the middle of the lock-step exchange: a message in flight
    // is lost.
    let (host_a, host_b, b_out) = keeper_3_on_host_b(&sandbox, &hosts, &["--heartbeat-timeout", "3"]);
    let root = sandbox.out("a").parent().unwrap().display().to_string();
    let bridges = pids_with_all(&["learnpnp-bridge", "--side host", &root]);
    assert_eq!(bridges.len(), 1, "{bridges:?}");
    kill(bridges[0], libc::SIGKILL);
    let a_output = host_a.wait_with_output().unwrap();
    let _ = host_b.wait_with_output().unwrap();
    let a = summary(&sandbox.out("a"));
    let faults = a["faults"].to_string();
    assert!(
        faults.contains("the bridge exited"),
        "{faults}\n{}",
        text(&a_output.stderr)
    );
    if a["complete"] == true {
        // No message was in flight: the restarted bridge carried on.
        assert!(a_output.status.success(), "{}", text(&a_output.stderr));
        eprintln!("the bridge was killed with no message in flight: the run went on");
    } else {
        let failure = a["failure"].as_str().unwrap_or_default();
        assert!(
            failure.contains("lock-step stalled: no cycle for 9 s"),
            "{a}\n{}",
            text(&a_output.stderr)
        );
        eprintln!("a message was lost with the bridge: the stalled run was stopped after 9 s");
    }
    // No learned value lost: every keeper's last checkpoint, host B's
    // included (shipped back), is in the run's files and loads.
    for file in ["values.bin", "values-agent2.bin", "values-agent3.bin"] {
        let values = learnpnp::persist::load(&sandbox.out("a").join("runs/run-0").join(file));
        assert!(values.is_ok(), "{file}: {values:?}");
    }
    let b = remote_summary(&b_out);
    let mut used = prefixes(&a);
    used.extend(b["ipc_prefix"].as_str().map(str::to_string));
    sandbox.assert_clean(&used);
}
