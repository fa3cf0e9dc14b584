//! A run with a view: the agents publish their live feed on iceoryx2, the
//! read-only view process (`learnpnp-view`) serves it; the run plays the
//! same episodes as without one, garbage on a feed is refused and counted,
//! and a killed view does not stop the run. The runs are short (150
//! episodes): each is held (its simulator stopped) until the test is ready.

use std::collections::HashMap;
use std::fs;
use std::net::SocketAddr;
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

use futures_util::{SinkExt, StreamExt};
use learnpnp::feed::FeedEvent;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::tungstenite::client::IntoClientRequest;

use learnpnp_system::ipc::feed::feed_service;
use learnpnp_system::multiprocess::supervisor::run_work_dir;
use learnpnp_system::multiprocess::view_process::ViewCounts;
use serde_json::Value;
use shm_layouts::{FeedHeader, PROTOCOL_VERSION};

use crate::support::{
    Sandbox, assert_plays_in_process, foreign_node, identity, kill, pids_with_all, prefixes, stop, summary, wait_until,
};

/// The runs' protocol: the short one without its seed and algorithm.
fn protocol() -> &'static [&'static str] {
    &crate::support::SHORT[..8]
}

/// The learner and seed of every run here.
const LEARNER: &[&str] = &["--seed", "3", "--algo", "soft-sosmc"];

/// Starts run `system` of `sandbox` with a view (`view_args`), and stops its
/// simulator (SIGSTOP) before it has played the run out: the test does what
/// it must while the run waits, then lets it go on with [`resume`]. Lock-step,
/// the run plays the same episodes however long it waits.
fn start_held(sandbox: &Sandbox, view_args: &[&std::ffi::OsStr]) -> (std::process::Child, i32) {
    let child = sandbox
        .supervisor("system", LEARNER)
        .args(protocol())
        // Held, the simulator sends no heartbeat: not taken as hung on a loaded machine.
        .args(["--heartbeat-timeout", "60"])
        .args(view_args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The work directory is found anew: it appears when the supervisor starts.
    let work = || run_work_dir(&sandbox.out("system"), 0);
    let simulator = || pids_with_all(&["learnpnp-sim", &work().to_string_lossy()]);
    assert!(wait_until(Duration::from_secs(60), || simulator().len() == 1));
    let pid = simulator()[0];
    stop(pid);
    (child, pid)
}

/// Lets a run held by [`start_held`] go on.
fn resume(simulator: i32) {
    kill(simulator, libc::SIGCONT);
}

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

/// The address run 0's view serves on, once its log names it.
fn view_address(out: &Path) -> SocketAddr {
    let line = || {
        let log = fs::read_to_string(run_work_dir(out, 0).join("view.log")).unwrap_or_default();
        log.lines()
            .find_map(|l| l.strip_prefix("view: http://"))
            .and_then(|rest| rest.split('/').next())
            .and_then(|address| address.parse().ok())
    };
    assert!(
        wait_until(Duration::from_secs(60), || line().is_some()),
        "the view names its address"
    );
    line().unwrap()
}

/// What a client of the view's Foxglove WebSocket protocol receives on
/// `wanted` channels until `enough` says so, the view closes, or a minute
/// passes; `subscribed` is called once it has subscribed.
fn watch(
    address: SocketAddr,
    wanted: &[&str],
    subscribed: impl FnOnce(),
    enough: impl Fn(&[FeedEvent]) -> bool,
) -> Vec<FeedEvent> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    runtime.block_on(async {
        let mut request = format!("ws://{address}/").into_client_request().unwrap();
        request
            .headers_mut()
            .insert("Sec-WebSocket-Protocol", "foxglove.sdk.v1".parse().unwrap());
        let (mut socket, _) = tokio_tungstenite::connect_async(request).await.unwrap();
        let mut topics: HashMap<u64, String> = HashMap::new();
        let mut received = Vec::new();
        let deadline = Instant::now() + Duration::from_secs(60);
        let mut subscribed = Some(subscribed);
        while Instant::now() < deadline && !enough(&received) {
            let message = match tokio::time::timeout(Duration::from_secs(5), socket.next()).await {
                Ok(Some(Ok(message))) => message,
                Ok(None | Some(Err(_))) => break,
                Err(_) => continue,
            };
            match message {
                Message::Text(text) => {
                    let json: Value = serde_json::from_str(&text).unwrap();
                    if json["op"] == "advertise" {
                        for channel in json["channels"].as_array().unwrap() {
                            let topic = channel["topic"].as_str().unwrap().to_owned();
                            topics.insert(channel["id"].as_u64().unwrap(), topic);
                        }
                    }
                    if subscribed.is_some() && topics.len() >= wanted.len() {
                        let subscriptions: Vec<Value> = topics
                            .iter()
                            .filter(|(_, topic)| wanted.contains(&topic.as_str()))
                            .map(|(id, _)| serde_json::json!({ "id": id, "channelId": id }))
                            .collect();
                        let subscribe = serde_json::json!({ "op": "subscribe", "subscriptions": subscriptions });
                        socket.send(Message::text(subscribe.to_string())).await.unwrap();
                        if let Some(subscribed) = subscribed.take() {
                            subscribed();
                        }
                    }
                }
                Message::Binary(data) if data.len() > 13 && data[0] == 1 => {
                    let subscription = u32::from_le_bytes(data[1..5].try_into().unwrap());
                    let topic = &topics[&u64::from(subscription)];
                    received.push(FeedEvent::from_payload(topic, &data[13..]).expect("a record of the feed"));
                }
                Message::Close(_) => break,
                _ => {}
            }
        }
        received
    })
}

#[test]
fn a_client_sees_every_agent_and_process_and_the_run_plays_the_same_episodes() {
    let sandbox = Sandbox::new("view");
    let out = sandbox.out("system");
    let (child, simulator) = start_held(&sandbox, &["--view=127.0.0.1:0".as_ref()]);
    let address = view_address(&out);
    assert!(address.ip().is_loopback());
    let processes = ["simulator", "keeper 1", "keeper 2", "keeper 3", "view"];
    let seen = |received: &[FeedEvent]| {
        let agents = |kind: usize| {
            (0..3).all(|a| {
                received.iter().any(|e| match e {
                    FeedEvent::Marking(m) => kind == 1 && m.source.agent == a,
                    FeedEvent::Choice(c) => kind == 2 && c.source.agent == a,
                    _ => false,
                })
            })
        };
        let healthy = processes.iter().all(|p| {
            received
                .iter()
                .any(|e| matches!(e, FeedEvent::Health(h) if h.process == *p))
        });
        agents(1) && agents(2) && healthy
    };
    // Subscribed, the client lets the run go on; it reads until it has seen
    // enough or the view closes at the run's end (its last records sent).
    let received = watch(
        address,
        &["/learnpnp/marking", "/learnpnp/choice", "/learnpnp/health"],
        || resume(simulator),
        seen,
    );
    assert!(
        seen(&received),
        "markings and choices of every agent, every process's health"
    );
    assert_plays_in_process(child, &sandbox, "3", protocol());
    let s = summary(&out);
    assert_eq!(s["complete"], true);
    assert_eq!(s["restarts"], 0);
    let view = &s["view"];
    assert!(view["feed"]["received"].as_u64().unwrap() > 0, "{view}");
    assert_eq!(view["feed"]["rejected"]["content"], 0, "{view}");
    sandbox.assert_clean(&prefixes(&s));
}

#[test]
fn garbage_on_a_feed_is_refused_and_counted_and_a_killed_view_does_not_stop_the_run() {
    let sandbox = Sandbox::new("view-garbage");
    let out = sandbox.out("system");
    let jsonl = sandbox.out("feed.jsonl");
    let (child, simulator) = start_held(&sandbox, &["--view-jsonl".as_ref(), jsonl.as_os_str()]);
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
        let publisher = feed_service(&node, 0)
            .unwrap()
            .publisher_builder()
            .initial_max_slice_len(4096)
            .create()
            .unwrap();
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
    // The view serves on, and has written what it refused.
    let served = healths();
    assert!(
        wait_until(Duration::from_secs(10), || healths() > served),
        "the view serves on"
    );
    let work = run_work_dir(&out, 0);
    let refused = || ViewCounts::load(&work).feed.rejected.total();
    assert!(wait_until(Duration::from_secs(10), || refused() == 5), "{}", refused());
    // Killed, the view does not stop the run.
    let views = pids_with_all(&["learnpnp-view", &work.to_string_lossy()]);
    assert_eq!(views.len(), 1, "{views:?}");
    kill(views[0], libc::SIGKILL);
    resume(simulator);
    assert_plays_in_process(child, &sandbox, "3", protocol());
    let s = summary(&out);
    assert_eq!(s["complete"], true);
    let fault = &s["faults"][0];
    assert!(
        fault["kind"].as_str().unwrap().contains("the view exited: signal 9"),
        "{fault}"
    );
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
