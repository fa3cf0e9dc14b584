//! Intruders on a run's link between hosts, each in a process of its own on
//! host B's network namespace (this test binary run again, as the ignored
//! test [`intruder`], told what to do by environment variables), attacking
//! while a two-host lock-step run plays: one with no certificate, one with a
//! certificate of another CA (named as host B), one with host B's own
//! certificate misused for keys it may not publish. Each attack of the
//! secure-link issue has its test: reading the run, forging a keeper's
//! commands and reports, ordering the run to stop, replaying an episode's
//! begin, shipping files into host A's run directory. Every one must be
//! refused and counted, and the run must play exactly the one-host episodes.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use shm_layouts::{
    AgentReport, Control, Header, Heartbeat, KeeperCommand, SENDER_SUPERVISOR, command, control, episode, report,
};
use zenoh::{Config, Session, Wait};

use crate::hosts::{Certs, Hosts, finished, host_a, keeper_3_remote, remote, remote_summary};
use crate::support::{SHORT, Sandbox, first_episode_event, prefixes, summary, wait_until};
use crate::util::text;

/// What an intruder holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Credentials {
    /// The run's CA certificate (it is no secret), no certificate of its own.
    None,
    /// A certificate named as host B's, of another CA.
    OtherCa,
    /// Host B's own certificate and key.
    HostB,
}

impl Credentials {
    fn name(self) -> &'static str {
        match self {
            Credentials::None => "none",
            Credentials::OtherCa => "other-ca",
            Credentials::HostB => "host-b",
        }
    }

    fn parse(s: &str) -> Self {
        match s {
            "none" => Credentials::None,
            "other-ca" => Credentials::OtherCa,
            _ => Credentials::HostB,
        }
    }
}

/// What the intruder tries, each an attack that worked over the plain TCP link.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Attack {
    /// Ask for the run and read every message.
    Eavesdrop,
    /// Publish keeper 1's commands and a report in keeper 1's name.
    ForgeCommands,
    /// Order the run to stop, and the keepers to checkpoint.
    Stop,
    /// Replay an old episode's begin.
    ReplayBegin,
    /// Ship files into host A's run directory (over the spec, over keeper 1's values).
    ShipFiles,
    /// Ship files under names host B may use, but not what their names say
    /// (text as histograms and values), and more of them than a run has.
    ShipBadFiles,
    /// Report keeper 3 lost: naming its live process, and a made-up one.
    KeeperLost,
    /// Subscribe to keeper 3's snapshots and stop reading for 20 s.
    HangingReader,
    /// Send keeper 3's commands with the right type and size but another
    /// sender in the header, another run, NaN or an unknown kind; and a
    /// heartbeat in keeper 3's name (host B's bridge refuses it).
    ForgeContent,
}

impl Attack {
    fn name(self) -> &'static str {
        match self {
            Attack::Eavesdrop => "eavesdrop",
            Attack::ForgeCommands => "forge-commands",
            Attack::Stop => "stop",
            Attack::ReplayBegin => "replay-begin",
            Attack::ShipFiles => "ship-files",
            Attack::ShipBadFiles => "ship-bad-files",
            Attack::KeeperLost => "keeper-lost",
            Attack::HangingReader => "hanging-reader",
            Attack::ForgeContent => "forge-content",
        }
    }

    fn parse(s: &str) -> Self {
        [
            Attack::Eavesdrop,
            Attack::ForgeCommands,
            Attack::Stop,
            Attack::ReplayBegin,
            Attack::ShipFiles,
            Attack::ShipBadFiles,
            Attack::KeeperLost,
            Attack::HangingReader,
            Attack::ForgeContent,
        ]
        .into_iter()
        .find(|a| a.name() == s)
        .unwrap()
    }
}

const ENV_ATTACK: &str = "LEARNPNP_INTRUDER_ATTACK";
const ENV_CREDENTIALS: &str = "LEARNPNP_INTRUDER_CREDENTIALS";
const ENV_ENDPOINT: &str = "LEARNPNP_INTRUDER_ENDPOINT";
const ENV_CA: &str = "LEARNPNP_INTRUDER_CA";
const ENV_CERT_DIR: &str = "LEARNPNP_INTRUDER_CERT_DIR";

/// How many times each forged message is sent.
const FORGERIES: usize = 40;

/// Histograms of keeper 3 the intruder ships.
const BAD_HISTOGRAMS: usize = 70;

/// How long the hanging reader stops reading.
const HANG: Duration = Duration::from_secs(20);

/// The intruder's Zenoh session: a client of host A's bridge.
fn open(endpoint: &str, credentials: Credentials, ca: &str, cert_dir: &str) -> Result<Session, String> {
    let mut config = Config::default();
    let set = |config: &mut Config, key: &str, value: String| config.insert_json5(key, &value).unwrap();
    set(&mut config, "mode", "\"client\"".into());
    set(&mut config, "scouting/multicast/enabled", "false".into());
    set(&mut config, "connect/endpoints", json!([endpoint]).to_string());
    set(&mut config, "connect/timeout_ms", "4000".into());
    set(&mut config, "connect/exit_on_failure", "true".into());
    let tls = "transport/link/tls";
    set(
        &mut config,
        &format!("{tls}/root_ca_certificate"),
        json!(ca).to_string(),
    );
    set(&mut config, &format!("{tls}/verify_name_on_connect"), "true".into());
    if credentials != Credentials::None {
        let dir = Path::new(cert_dir);
        let path = |f: &str| json!(dir.join(f).display().to_string()).to_string();
        set(&mut config, &format!("{tls}/enable_mtls"), "true".into());
        set(&mut config, &format!("{tls}/connect_certificate"), path("cert.pem"));
        set(&mut config, &format!("{tls}/connect_private_key"), path("key.pem"));
    }
    zenoh::open(config).wait().map_err(|e| e.to_string())
}

/// A layout's bytes, as the bridge carries them.
fn bytes_of<T: Copy>(value: &T) -> Vec<u8> {
    // SAFETY: the layouts are repr(C) plain data without padding.
    unsafe { std::slice::from_raw_parts((value as *const T).cast::<u8>(), size_of::<T>()) }.to_vec()
}

/// Publishes `value` on `key` tagged as type `name`, [`FORGERIES`] times.
fn forge<T: Copy>(session: &Session, key: &str, name: &str, value: &T) {
    for _ in 0..FORGERIES {
        let _ = session
            .put(key, bytes_of(value))
            .attachment(format!("{name};{}", shm_layouts::PROTOCOL_VERSION))
            .wait();
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The run's description, as host B's certificate may ask for it.
fn run_info(session: &Session) -> Option<Value> {
    let replies = session
        .get("learnpnp/run-info")
        .timeout(Duration::from_secs(2))
        .wait()
        .ok()?;
    let reply = replies.recv().ok()?;
    let sample = reply.result().ok()?;
    serde_json::from_slice(&sample.payload().to_bytes()).ok()
}

/// Runs the attack with the session; what the intruder saw.
fn attack(session: &Session, attack: Attack) -> Value {
    let Some(info) = run_info(session) else {
        return json!({ "connected": true, "run_info": false });
    };
    let prefix = info["prefix"].as_str().unwrap().trim_end_matches('_').to_string();
    let run_id = info["run_id"].as_u64().unwrap();
    let key = |service: &str| format!("learnpnp/{prefix}/{service}");
    // Wait until the run plays: host A's heartbeats, which host B may read.
    let beats = session.declare_subscriber(key("learnpnp/heartbeat/*")).wait().unwrap();
    let deadline = Instant::now() + Duration::from_secs(30);
    while beats.try_recv().ok().flatten().is_none() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(10));
    }
    let mut received = 0;
    match attack {
        Attack::Eavesdrop => {
            let all = session.declare_subscriber("learnpnp/**").wait().unwrap();
            let keeper_1 = session
                .declare_subscriber(key("learnpnp/keeper/0/snapshot"))
                .wait()
                .unwrap();
            std::thread::sleep(Duration::from_secs(2));
            // What host B's agent (keeper 3) may read comes in too (the
            // heartbeats, the episode events, its snapshots); keepers 1 and
            // 2's messages must not.
            received = all
                .drain()
                .chain(keeper_1.drain())
                .filter(|s| {
                    ["/keeper/0/", "/keeper/1/"]
                        .iter()
                        .any(|k| s.key_expr().as_str().contains(k))
                })
                .count();
        }
        Attack::ForgeCommands => {
            let forged = KeeperCommand {
                header: Header::new(0, run_id),
                episode: 1,
                cycle_seq: 1,
                kind: command::NONE,
                flags: command::FLAG_IDLE,
                arg0: 0.0,
                arg1: 0.0,
            };
            forge(
                session,
                &key("learnpnp/keeper/0/command"),
                "learnpnp::KeeperCommand",
                &forged,
            );
            // A report in keeper 1's name, on keeper 3's key (which host B may use).
            let report = AgentReport {
                header: Header::new(0, run_id),
                episode: 1,
                kind: report::ENDED,
                pid: 0,
                exploratory: 0,
                reserved: [0; 7],
            };
            forge(
                session,
                &key("learnpnp/agent-report/2"),
                "learnpnp::AgentReport",
                &report,
            );
        }
        Attack::Stop => {
            let stop = Control {
                header: Header::new(SENDER_SUPERVISOR, run_id),
                command: control::STOP,
                target: control::ALL,
                sequence: 1,
                pid: 0,
                reserved: 0,
            };
            // As host A's supervisor, and as host B's ordering every process.
            forge(session, &key("learnpnp/control/host-a"), "learnpnp::Control", &stop);
            forge(session, &key("learnpnp/control/host-b"), "learnpnp::Control", &stop);
            let checkpoint = Control {
                command: control::CHECKPOINT,
                target: 0,
                ..stop
            };
            forge(
                session,
                &key("learnpnp/control/host-b"),
                "learnpnp::Control",
                &checkpoint,
            );
        }
        Attack::ReplayBegin => {
            let begin = first_episode_event(run_id, episode::BEGIN);
            forge(session, &key("learnpnp/episode"), "learnpnp::EpisodeEvent", &begin);
        }
        Attack::ShipFiles => {
            for name in ["spec.json", "values.bin", "values-agent2.bin", "intruder.txt"] {
                let _ = session.put(key(&format!("file/{name}")), b"forged".to_vec()).wait();
            }
        }
        Attack::ShipBadFiles => {
            let garbage = b"these are 23 bytes, no!".to_vec();
            // 70 histograms of keeper 3, one of the floor.
            for pid in 1..=BAD_HISTOGRAMS {
                let name = format!("file/compute-keeper3.{pid}.hdr");
                let _ = session.put(key(&name), garbage.clone()).wait();
            }
            let _ = session.put(key("file/floor-remote-host.1.hdr"), garbage.clone()).wait();
            // Keeper 3's values, sent again and again until the run ends
            // (past host B's own shipment), within a bound.
            let deadline = Instant::now() + Duration::from_secs(90);
            let mut quiet = 0;
            while Instant::now() < deadline && quiet < 15 {
                let _ = session.put(key("file/values-agent3.bin"), garbage.clone()).wait();
                std::thread::sleep(Duration::from_millis(200));
                // 3 s without a heartbeat: the run is over.
                quiet = if beats.drain().count() == 0 { quiet + 1 } else { 0 };
            }
        }
        Attack::KeeperLost => {
            // Keeper 3's process, from its heartbeat (host B may read it).
            let keeper_3 = session.declare_subscriber(key("learnpnp/heartbeat/2")).wait().unwrap();
            let pid = loop {
                if let Ok(sample) = keeper_3.recv() {
                    let bytes = sample.payload().to_bytes();
                    if bytes.len() == size_of::<Heartbeat>() {
                        // SAFETY: the bytes are a heartbeat's (plain data).
                        let beat: Heartbeat = unsafe { std::ptr::read_unaligned(bytes.as_ptr().cast()) };
                        break beat.pid;
                    }
                }
            };
            for named in [pid, 4_000_000] {
                let lost = Control {
                    header: Header::new(SENDER_SUPERVISOR, run_id),
                    command: control::KEEPER_LOST,
                    target: 2,
                    sequence: 1,
                    pid: named,
                    reserved: 0,
                };
                let _ = session
                    .put(key("learnpnp/control/host-b"), bytes_of(&lost))
                    .attachment(format!("learnpnp::Control;{}", shm_layouts::PROTOCOL_VERSION))
                    .wait();
                std::thread::sleep(Duration::from_millis(500));
            }
            received = 2;
        }
        Attack::HangingReader => {
            let hanging = session
                .declare_subscriber(key("learnpnp/keeper/2/snapshot"))
                .callback(|_| std::thread::sleep(HANG))
                .wait()
                .unwrap();
            std::thread::sleep(HANG + Duration::from_secs(2));
            drop(hanging);
        }
        Attack::ForgeContent => {
            let good = KeeperCommand {
                header: Header::new(2, run_id),
                episode: 1,
                cycle_seq: 1,
                kind: command::DASH,
                flags: 0,
                arg0: 50.0,
                arg1: 0.0,
            };
            let forgeries = [
                KeeperCommand {
                    header: Header::new(0, run_id),
                    ..good
                },
                KeeperCommand {
                    header: Header::new(2, run_id + 1),
                    ..good
                },
                KeeperCommand { arg0: f64::NAN, ..good },
                KeeperCommand { kind: 99, ..good },
            ];
            for forged in &forgeries {
                forge(
                    session,
                    &key("learnpnp/keeper/2/command"),
                    "learnpnp::KeeperCommand",
                    forged,
                );
            }
            // Keeper 3's heartbeat, which host A's router passes on to host B's
            // bridge: it takes heartbeats of host A's processes only.
            let beat = Heartbeat {
                header: Header::new(2, run_id),
                pid: 1,
                state: shm_layouts::state::RUNNING,
                sequence: 1,
                episodes: 0,
                cycles: 0,
                rejected: [0; shm_layouts::reject::COUNT],
                missed_deadlines: 0,
                aborted_episodes: 0,
                checkpoints: 0,
                checkpoint_failures: 0,
                late_cycles: 0,
            };
            forge(session, &key("learnpnp/heartbeat/2"), "learnpnp::Heartbeat", &beat);
        }
    }
    // Give the last puts time to leave before the session closes (under
    // load a close could drop what is still queued).
    std::thread::sleep(Duration::from_millis(500));
    json!({ "connected": true, "run_info": true, "received": received })
}

/// What the impostor of host A does: listens where host A would, with a
/// certificate of another CA named as host A's, for this long.
const IMPOSTOR_FOR: Duration = Duration::from_secs(30);

/// The impostor's session: a router on `endpoint` with the certificate in `cert_dir`.
fn impostor(endpoint: &str, ca: &str, cert_dir: &str) -> Result<Session, String> {
    let mut config = Config::default();
    let set = |config: &mut Config, key: &str, value: String| config.insert_json5(key, &value).unwrap();
    let dir = Path::new(cert_dir);
    let path = |f: &str| json!(dir.join(f).display().to_string()).to_string();
    set(&mut config, "mode", "\"router\"".into());
    set(&mut config, "scouting/multicast/enabled", "false".into());
    set(
        &mut config,
        "listen/endpoints",
        json!([format!("{endpoint}?multistream=0")]).to_string(),
    );
    let tls = "transport/link/tls";
    set(
        &mut config,
        &format!("{tls}/root_ca_certificate"),
        json!(ca).to_string(),
    );
    set(&mut config, &format!("{tls}/enable_mtls"), "true".into());
    set(&mut config, &format!("{tls}/listen_certificate"), path("cert.pem"));
    set(&mut config, &format!("{tls}/listen_private_key"), path("key.pem"));
    zenoh::open(config).wait().map_err(|e| e.to_string())
}

/// Not a test of its own: the intruder process that [`attacked`] starts
/// (it does nothing when its environment does not name an attack).
#[test]
#[ignore = "an intruder process started by the attack tests"]
fn intruder() {
    let Ok(attack_name) = std::env::var(ENV_ATTACK) else {
        return;
    };
    let env = |k: &str| std::env::var(k).unwrap();
    if attack_name == "impostor" {
        let session = impostor(&env(ENV_ENDPOINT), &env(ENV_CA), &env(ENV_CERT_DIR));
        println!("INTRUDER {}", json!({ "listening": session.is_ok() }));
        std::thread::sleep(IMPOSTOR_FOR);
        return;
    }
    let credentials = Credentials::parse(&env(ENV_CREDENTIALS));
    let seen = match open(&env(ENV_ENDPOINT), credentials, &env(ENV_CA), &env(ENV_CERT_DIR)) {
        Ok(session) => {
            let seen = attack(&session, Attack::parse(&attack_name));
            let _ = session.close().wait();
            seen
        }
        Err(e) => json!({ "connected": false, "error": e }),
    };
    println!("INTRUDER {seen}");
}

/// This test binary run again as the intruder process ([`intruder`]),
/// told to do `attack` against `endpoint` with the CA `ca` and the
/// certificate in `certs`.
fn intruder_command(attack: &str, endpoint: &str, ca: &Path, certs: &Path) -> Command {
    let mut command = Command::new(std::env::current_exe().unwrap());
    command
        .args([
            "--exact",
            "intruders::intruder",
            "--ignored",
            "--nocapture",
            "--test-threads",
            "1",
        ])
        .env(ENV_ATTACK, attack)
        .env(ENV_ENDPOINT, endpoint)
        .env(ENV_CA, ca)
        .env(ENV_CERT_DIR, certs);
    command
}

/// Starts an intruder with `credentials` on host B for `attack`.
fn start_intruder(
    hosts: &Hosts,
    attack: Attack,
    credentials: Credentials,
    ca: &Path,
    certs: &Path,
) -> std::process::Child {
    let mut command = intruder_command(attack.name(), &hosts.endpoint(), ca, certs);
    command.env(ENV_CREDENTIALS, credentials.name());
    hosts
        .on(false, command)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// What an intruder printed it saw.
fn seen(child: std::process::Child) -> Value {
    let output = child.wait_with_output().unwrap();
    let stdout = text(&output.stdout);
    let line = stdout
        .lines()
        .find_map(|l| l.split_once("INTRUDER ").map(|(_, seen)| seen))
        .unwrap_or_else(|| panic!("the intruder said nothing: {stdout}\n{}", text(&output.stderr)));
    serde_json::from_str(line).unwrap()
}

/// The one-host run's episodes, played once for every attack test.
fn one_host_episodes() -> &'static [u8] {
    static EPISODES: OnceLock<Vec<u8>> = OnceLock::new();
    EPISODES.get_or_init(|| {
        let sandbox = Sandbox::new("hosts-reference");
        let one = sandbox.supervisor("one", &SHORT).output().unwrap();
        assert!(one.status.success(), "{}", text(&one.stderr));
        let episodes = fs::read(sandbox.out("one").join("episodes.csv")).unwrap();
        sandbox.assert_clean(&prefixes(&summary(&sandbox.out("one"))));
        episodes
    })
}

/// A two-host lock-step run attacked by three intruders trying `attack`:
/// checks that it played the one-host episodes, that neither intruder
/// without a certificate of the run's CA got in and that both were counted;
/// returns host A's summary and the misused certificate's intruder's view.
fn attacked(attack: Attack) -> (Value, Value) {
    let reference = one_host_episodes();
    let sandbox = Sandbox::new(&format!("hosts-{}", attack.name()));
    let hosts = Hosts::new();
    let certs: Certs = hosts.certs(&sandbox.out("certs"));
    // Another CA, with a certificate named as host B's.
    let other: PathBuf = sandbox.out("other-ca");
    hosts.certs(&other);
    let endpoint = hosts.endpoint();
    let host_a = host_a(&hosts, &sandbox, "a", &keeper_3_remote(&endpoint, &certs));
    let b_out = sandbox.out("host-b");
    let ca = Path::new(&certs.host_b).join("ca.pem");
    let host_b = hosts
        .on(false, remote(&sandbox, &b_out, &endpoint, &certs))
        .spawn()
        .unwrap();
    // Once host B has joined, host A's bridge listens: the intruders come.
    assert!(wait_until(Duration::from_secs(60), || b_out
        .join("run-info.json")
        .is_file()));
    let intruders: Vec<_> = [
        (Credentials::None, PathBuf::new()),
        (Credentials::OtherCa, other.join("host-b")),
        (Credentials::HostB, PathBuf::from(&certs.host_b)),
    ]
    .into_iter()
    .map(|(credentials, dir)| (credentials, start_intruder(&hosts, attack, credentials, &ca, &dir)))
    .collect();
    let views: Vec<(Credentials, Value)> = intruders.into_iter().map(|(c, child)| (c, seen(child))).collect();
    finished(host_b);
    finished(host_a);
    let a = summary(&sandbox.out("a"));
    assert_eq!(
        fs::read(sandbox.out("a").join("episodes.csv")).unwrap(),
        reference,
        "the attacked run played the one-host episodes: {a}"
    );
    assert_eq!(a["complete"], true, "{a}");
    // No peer held up host A's bridge until Zenoh gave up on it (a
    // subscriber that stops reading loses its own messages instead).
    let bridge_log = fs::read_to_string(sandbox.out("a").join("runs/run-0/bridge.log")).unwrap_or_default();
    assert!(
        !bridge_log.contains("Unable to push non droppable"),
        "host A's bridge blocked on a peer: {bridge_log}"
    );
    // Host B's own checkpoint came through whatever else arrived.
    let values = learnpnp::persist::load(&sandbox.out("a").join("runs/run-0/values-agent3.bin"));
    assert!(values.is_ok(), "{values:?}");
    for entry in fs::read_dir(sandbox.out("a").join("runs/run-0")).unwrap().flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        assert_ne!(name, "intruder.txt");
        assert_ne!(fs::read(entry.path()).ok().as_deref(), Some(&b"forged"[..]), "{name}");
    }
    for (credentials, view) in &views {
        match credentials {
            Credentials::HostB => assert_eq!(view["connected"], true, "{view}"),
            _ => assert_eq!(view["connected"], false, "{credentials:?}: {view}"),
        }
    }
    let refused = &a["link"]["refused"];
    assert!(
        refused["tls_handshake"].as_u64().unwrap() >= 2,
        "both intruders without a certificate of the run's CA refused at the handshake: {refused}"
    );
    let faults = a["faults"].to_string();
    assert!(
        faults.contains("the bridge refused"),
        "the refusals are a fault: {faults}"
    );
    let b = remote_summary(&b_out);
    let mut used = prefixes(&a);
    used.push(b["ipc_prefix"].as_str().unwrap().to_string());
    sandbox.assert_clean(&used);
    let misused = views.into_iter().find(|(c, _)| *c == Credentials::HostB).unwrap().1;
    (a, misused)
}

fn refused(a: &Value, reason: &str) -> u64 {
    a["link"]["refused"][reason].as_u64().unwrap()
}

#[test]
fn an_intruder_cannot_read_the_run() {
    let (a, misused) = attacked(Attack::Eavesdrop);
    // Host B's certificate may ask for the run, but not read keepers 1 and 2's messages.
    assert_eq!(misused["received"], 0, "{misused}");
    assert!(refused(&a, "access_denied") >= 2, "{}", a["link"]);
}

#[test]
fn forged_commands_and_reports_are_refused() {
    let (a, _) = attacked(Attack::ForgeCommands);
    assert!(refused(&a, "access_denied") >= 1, "keeper 1's key: {}", a["link"]);
    assert_eq!(
        refused(&a, "wrong_sender"),
        40,
        "keeper 1's report on keeper 3's key: {}",
        a["link"]
    );
}

#[test]
fn a_forged_stop_does_not_end_the_run() {
    let (a, _) = attacked(Attack::Stop);
    assert!(refused(&a, "access_denied") >= 1, "host A's key: {}", a["link"]);
    assert_eq!(
        refused(&a, "forbidden_order"),
        80,
        "a stop to every process and a checkpoint of keeper 1 from host B: {}",
        a["link"]
    );
    assert_eq!(a["link"]["stop_requests"], 0, "{}", a["link"]);
}

#[test]
fn a_replayed_begin_is_refused() {
    let (a, _) = attacked(Attack::ReplayBegin);
    assert!(refused(&a, "access_denied") >= 1, "{}", a["link"]);
}

#[test]
fn files_under_names_the_run_does_not_expect_are_refused() {
    let (a, _) = attacked(Attack::ShipFiles);
    // spec.json, keeper 1's and keeper 2's values, a file of any name.
    assert!(refused(&a, "access_denied") >= 4, "{}", a["link"]);
}

#[test]
fn files_that_are_not_what_their_names_say_are_refused_and_the_run_reports_without_them() {
    let (a, _) = attacked(Attack::ShipBadFiles);
    let link = &a["link"];
    // Keeper 3's histograms, the floor's, and the values at least once.
    assert!(refused(&a, "file_content") >= BAD_HISTOGRAMS as u64 + 2, "{link}");
    let listed = link["refused_files"].to_string();
    for name in ["compute-keeper3.1.hdr", "floor-remote-host.1.hdr", "values-agent3.bin"] {
        assert!(listed.contains(name), "{name}: {listed}");
    }
    let faults = a["faults"].to_string();
    assert!(faults.contains("host B's file 'values-agent3.bin' refused"), "{faults}");
    // Host A's own results are all there (`attacked` checked host B's values).
    assert!(a["experiment"].is_object(), "{a}");
}

#[test]
fn a_keeper_reported_lost_while_it_lives_is_refused_and_reported() {
    let (a, _) = attacked(Attack::KeeperLost);
    assert_eq!(
        refused(&a, "forbidden_order"),
        2,
        "the live process and a made-up one: {}",
        a["link"]
    );
    assert_eq!(a["aborted_episodes"], 0, "{a}");
    let events = a["link"]["agents_lost"].as_array().unwrap();
    assert_eq!(events.len(), 2, "{events:?}");
    assert!(
        events.iter().all(|e| e["accepted"] == false && e["agent"] == 3),
        "{events:?}"
    );
    let faults = a["faults"].to_string();
    assert!(faults.contains("host B reported agent 3 lost"), "{faults}");
}

#[test]
fn a_reader_that_stops_reading_does_not_hold_up_the_run() {
    // The attacked run must play the one-host episodes (checked by
    // `attacked`): nothing reached host B late or not at all.
    let (a, _) = attacked(Attack::HangingReader);
    let host_b = &a["link"]["host_b"];
    assert_eq!(host_b["lost"], 0, "{host_b}");
    assert_eq!(a["link"]["lost"], 0, "{}", a["link"]);
}

#[test]
fn commands_the_simulator_would_refuse_are_refused_on_the_link_and_host_b_reports_its_refusals() {
    let (a, _) = attacked(Attack::ForgeContent);
    let link = &a["link"];
    assert_eq!(refused(&a, "wrong_sender"), 40, "keeper 1 in the header: {link}");
    assert_eq!(refused(&a, "wrong_run"), 40, "{link}");
    assert_eq!(refused(&a, "bad_content"), 80, "NaN, an unknown kind: {link}");
    assert_eq!(
        a["rejected_messages"]["simulator"]["sender"], 0,
        "none reached the simulator: {a}"
    );
    // Host B's bridge refused the heartbeat in keeper 3's name; host A reports it.
    assert_eq!(link["host_b"]["refused"]["wrong_key"], 40, "{link}");
    let faults = a["faults"].to_string();
    assert!(faults.contains("host B's bridge refused"), "{faults}");
}

#[test]
fn host_b_refuses_a_host_a_of_another_ca_at_the_handshake_and_says_so() {
    let sandbox = Sandbox::new("hosts-impostor");
    let hosts = Hosts::new();
    let certs: Certs = hosts.certs(&sandbox.out("certs"));
    let other: Certs = hosts.certs(&sandbox.out("other-ca"));
    let endpoint = hosts.endpoint();
    let other_a = Path::new(&other.host_a);
    let command = intruder_command("impostor", &endpoint, &other_a.join("ca.pem"), other_a);
    let mut impostor = hosts
        .on(true, command)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(2));
    let b_out = sandbox.out("host-b");
    let started = Instant::now();
    let output = hosts
        .on(false, remote(&sandbox, &b_out, &endpoint, &certs))
        .output()
        .unwrap();
    let _ = impostor.kill();
    let _ = impostor.wait();
    let stderr = text(&output.stderr);
    assert!(!output.status.success(), "{stderr}");
    assert!(stderr.contains("refused at the TLS handshake"), "{stderr}");
    assert!(
        started.elapsed() < Duration::from_secs(50),
        "given up before the 60 s join timeout: {stderr}"
    );
    let link: Value = serde_json::from_str(&fs::read_to_string(b_out.join("link.json")).unwrap()).unwrap();
    assert!(link["refused"]["tls_handshake"].as_u64().unwrap() >= 3, "{link}");
}
