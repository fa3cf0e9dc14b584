//! The view served, recorded and monitored while an in-process experiment runs.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use futures_util::{SinkExt, StreamExt};
use learnpnp::experiment::options::{DomainName, ExperimentOptions};
use learnpnp::experiment::runner::{Completed, RunOptions, run_experiment};
use learnpnp::experiment::spec::{Algorithm, ExperimentSpec};
use learnpnp::feed::{CHANNELS, CurvePoint, FeedEvent, FeedSink, LatencySummary, ProcessHealth};
use learnpnp_view::{BUNDLE_CHANNEL, View, ViewOptions};
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::tungstenite::client::IntoClientRequest;

/// Parr and Russell's grid with SoSMC: a run of `episodes` learning episodes.
fn grid(episodes: u64) -> ExperimentSpec {
    ExperimentOptions {
        algo: Some(Algorithm::EpsSosmc),
        runs: Some(1),
        episodes: Some(episodes),
        eval_every: Some(episodes / 4),
        eval_episodes: Some(10),
        greedy_episodes: Some(10),
        seed: Some(7),
        ..ExperimentOptions::default()
    }
    .spec(DomainName::ParrRussell)
    .expect("a valid spec")
}

fn loopback_any_port() -> Option<SocketAddr> {
    Some("127.0.0.1:0".parse().expect("an address"))
}

/// Runs `spec` in this process, publishing to `view`.
fn run_watched(spec: &ExperimentSpec, view: &Arc<View>) {
    let feed: Arc<dyn FeedSink> = view.clone();
    let options = RunOptions {
        threads: 1,
        feed: Some(&feed),
        ..RunOptions::default()
    };
    run_experiment(spec, options, Completed::default()).expect("the experiment runs");
}

fn temp_file(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("learnpnp-view-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    dir.join(name)
}

/// A plain HTTP GET: the status line and the body.
fn http_get(address: SocketAddr, path: &str) -> (String, Vec<u8>) {
    let mut stream = TcpStream::connect(address).expect("the view accepts");
    write!(stream, "GET {path} HTTP/1.1\r\nHost: {address}\r\n\r\n").expect("the request is sent");
    let mut response = Vec::new();
    stream.read_to_end(&mut response).expect("the response is read");
    let end = response
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("a response head");
    let head = String::from_utf8_lossy(&response[..end]).into_owned();
    let status = head.lines().next().unwrap_or("").to_owned();
    (status, response[end + 4..].to_vec())
}

/// A queue longer than every record these tests' runs publish: a loaded
/// machine's view thread may fall behind the learner, and these tests check
/// what is recorded and served, not the drop policy (a full queue drops and
/// counts, which `View::dropped` reports).
const NO_DROPS: usize = 1 << 17;

/// The run of the marker curve point that tells the test the server took its
/// subscription (no experiment has that many runs).
const MARKER_RUN: u32 = u32::MAX;

#[test]
fn a_client_of_the_foxglove_protocol_sees_markings_and_choices_with_the_plans_labels() {
    let view = Arc::new(
        View::start(ViewOptions {
            address: loopback_any_port(),
            queue: NO_DROPS,
            ..ViewOptions::default()
        })
        .expect("the view starts"),
    );
    let address = view.address().expect("the view is served");
    assert!(address.ip().is_loopback());

    let (status, page) = http_get(address, "/");
    assert_eq!(status, "HTTP/1.1 200 OK");
    assert!(String::from_utf8_lossy(&page).contains("<html"));
    assert_eq!(http_get(address, "/app.js").0, "HTTP/1.1 200 OK");
    assert_eq!(http_get(address, "/nothing-here").0, "HTTP/1.1 404 Not Found");

    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let spec = grid(2_000);
    let health = ProcessHealth {
        process: "keeper 1".into(),
        pid: Some(4242),
        alive: true,
        heartbeat_age_ms: 12,
        restarts: 1,
        rejections: 0,
    };
    let latency = LatencySummary {
        process: "keeper 1".into(),
        measure: "compute".into(),
        count: 100,
        p50_us: 3,
        p90_us: 5,
        p99_us: 9,
        max_us: 40,
    };
    let received = runtime.block_on(async {
        let mut request = format!("ws://{address}/").into_client_request().expect("a request");
        request
            .headers_mut()
            .insert("Sec-WebSocket-Protocol", "foxglove.sdk.v1".parse().expect("a header"));
        let (mut socket, response) = tokio_tungstenite::connect_async(request).await.expect("the upgrade");
        assert_eq!(
            response
                .headers()
                .get("sec-websocket-protocol")
                .and_then(|v| v.to_str().ok()),
            Some("foxglove.sdk.v1")
        );
        // The channels are advertised on connection.
        let mut topics: HashMap<u64, String> = HashMap::new();
        while topics.len() < CHANNELS.len() {
            let message = tokio::time::timeout(Duration::from_secs(10), socket.next())
                .await
                .expect("the channels are advertised in time")
                .expect("the connection stays open")
                .expect("a message");
            if let Message::Text(text) = message {
                let json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
                if json["op"] == "advertise" {
                    for channel in json["channels"].as_array().expect("channels") {
                        assert_eq!(channel["encoding"], "json");
                        assert_eq!(channel["schemaEncoding"], "jsonschema");
                        topics.insert(
                            channel["id"].as_u64().expect("an id"),
                            channel["topic"].as_str().expect("a topic").to_owned(),
                        );
                    }
                }
            }
        }
        let wanted = [
            "/learnpnp/plan",
            "/learnpnp/marking",
            "/learnpnp/choice",
            "/learnpnp/episode",
            "/learnpnp/curve",
        ];
        let subscriptions: Vec<serde_json::Value> = topics
            .iter()
            .filter(|(_, topic)| wanted.contains(&topic.as_str()) || *topic == BUNDLE_CHANNEL)
            .map(|(id, _)| serde_json::json!({ "id": id, "channelId": id }))
            .collect();
        let subscribe = serde_json::json!({ "op": "subscribe", "subscriptions": subscriptions });
        socket
            .send(Message::text(subscribe.to_string()))
            .await
            .expect("the subscription is sent");
        // The run starts once the server has taken the subscription: a
        // marker curve point, published until it comes back, says so (the
        // protocol acknowledges no subscription; a fixed sleep is not enough
        // on a loaded machine).
        let marker = FeedEvent::Curve(CurvePoint {
            run: MARKER_RUN,
            episode: 0,
            value: 0.0,
        });
        let marker_deadline = Instant::now() + Duration::from_secs(60);
        'subscribed: while Instant::now() < marker_deadline {
            view.publish(&marker);
            while let Ok(Some(Ok(message))) = tokio::time::timeout(Duration::from_millis(100), socket.next()).await {
                if let Message::Binary(data) = message {
                    let subscription = u32::from_le_bytes(data[1..5].try_into().expect("4 bytes"));
                    let topic = &topics[&u64::from(subscription)];
                    if FeedEvent::from_payload(topic, &data[13..]).as_ref() == Some(&marker) {
                        break 'subscribed;
                    }
                }
            }
        }
        // A process's health and latency, as a view process publishes them:
        // the page (subscribed to the bundle, not to their channels) is sent
        // them in the bundle.
        view.publish(&FeedEvent::Health(health.clone()));
        view.publish(&FeedEvent::Latency(latency.clone()));
        let runner = {
            let (view, spec) = (view.clone(), spec.clone());
            std::thread::spawn(move || run_watched(&spec, &view))
        };
        let mut received: Vec<FeedEvent> = Vec::new();
        let mut bundles: Vec<serde_json::Value> = Vec::new();
        let deadline = Instant::now() + Duration::from_secs(60);
        let kinds = |received: &[FeedEvent]| received.iter().map(FeedEvent::kind).collect::<HashSet<_>>();
        // Until every kind has come and a choice shows values learned.
        let learned = |received: &[FeedEvent]| {
            received
                .iter()
                .any(|e| matches!(e, FeedEvent::Choice(c) if c.options.iter().any(|o| o.updates > 0)))
        };
        while (kinds(&received).len() < wanted.len() || !learned(&received) || bundles.is_empty())
            && Instant::now() < deadline
        {
            let Ok(Some(Ok(message))) = tokio::time::timeout(Duration::from_secs(5), socket.next()).await else {
                continue;
            };
            if let Message::Binary(data) = message {
                assert_eq!(data[0], 1, "message data");
                let subscription = u32::from_le_bytes(data[1..5].try_into().expect("4 bytes"));
                let topic = &topics[&u64::from(subscription)];
                if topic == BUNDLE_CHANNEL {
                    bundles.push(serde_json::from_slice(&data[13..]).expect("JSON"));
                    continue;
                }
                let event = FeedEvent::from_payload(topic, &data[13..]).expect("a record of the feed");
                if !matches!(&event, FeedEvent::Curve(c) if c.run == MARKER_RUN) {
                    received.push(event);
                }
            }
        }
        runner.join().expect("the run ends");
        // Each bundle sums up the next stretch of the markings, choices and
        // episode ends on their own channels (which come first).
        let paced: Vec<&FeedEvent> = received
            .iter()
            .filter(|e| matches!(e, FeedEvent::Marking(_) | FeedEvent::Choice(_) | FeedEvent::Episode(_)))
            .collect();
        let mut rest = paced.as_slice();
        for bundle in &bundles {
            let agents = bundle["agents"].as_array().expect("agents");
            assert!(agents.len() <= 1, "one agent: {bundle}");
            // A bundle sent before the run's first records holds only the process.
            let Some(agent) = agents.first() else { continue };
            let stretch_len = ["markings", "sub_plan_markings", "choices", "episodes"]
                .iter()
                .map(|count| agent[*count].as_u64().expect("a count"))
                .sum::<u64>();
            let stretch_len = usize::try_from(stretch_len).expect("a length");
            assert!(stretch_len > 0 && stretch_len <= rest.len(), "{bundle}");
            let (stretch, after) = rest.split_at(stretch_len);
            rest = after;
            assert_eq!(agent, &sum_up(stretch), "{bundle}");
        }
        let listed = |field: &str| -> Vec<serde_json::Value> {
            bundles
                .iter()
                .flat_map(|b| b[field].as_array().expect("a list").clone())
                .collect()
        };
        assert_eq!(listed("processes"), [serde_json::to_value(&health).expect("JSON")]);
        assert_eq!(listed("latency"), [serde_json::to_value(&latency).expect("JSON")]);
        received
    });
    let plan = received
        .iter()
        .find_map(|e| match e {
            FeedEvent::Plan(p) => Some(p.clone()),
            _ => None,
        })
        .expect("the plan's shape arrived");
    let labels: HashSet<&str> = plan.places.iter().map(|p| p.label.as_str()).collect();
    let markings: Vec<_> = received
        .iter()
        .filter_map(|e| match e {
            FeedEvent::Marking(m) => Some(m),
            _ => None,
        })
        .collect();
    let choices: Vec<_> = received
        .iter()
        .filter_map(|e| match e {
            FeedEvent::Choice(c) => Some(c),
            _ => None,
        })
        .collect();
    assert!(!markings.is_empty() && !choices.is_empty());
    for m in &markings {
        assert_eq!(m.tokens.len(), plan.places.len());
        assert!(m.marked.iter().all(|p| labels.contains(p.label.as_str())));
    }
    for c in &choices {
        assert!(labels.contains(c.choice_point.as_str()), "{}", c.choice_point);
        assert!(c.options.len() >= 2);
        assert_eq!(c.explored, c.taken != c.greedy);
    }
    // Some options are learned about as the run goes.
    assert!(choices.iter().any(|c| c.options.iter().any(|o| o.updates > 0)));
    assert!(received.iter().any(|e| matches!(e, FeedEvent::Curve(_))));
    let view = Arc::into_inner(view).expect("the run let go of the view");
    assert_eq!(view.dropped(), 0);
    view.close().expect("the view closes");
}

#[test]
fn a_recording_holds_every_record_published_uncompressed() {
    let file = temp_file("run.mcap");
    let view = Arc::new(
        View::start(ViewOptions {
            record_mcap: Some(file.clone()),
            queue: NO_DROPS,
            ..ViewOptions::default()
        })
        .expect("the view starts"),
    );
    run_watched(&grid(300), &view);
    let view = Arc::into_inner(view).expect("the run let go of the view");
    assert_eq!(view.dropped(), 0);
    let counts = view.close().expect("the recording completes");
    let bytes = std::fs::read(&file).expect("the recording is under its final name");
    let mut part = file.clone().into_os_string();
    part.push(".part");
    assert!(!PathBuf::from(part).exists());

    let mut recorded: BTreeMap<String, u64> = BTreeMap::new();
    for message in mcap::MessageStream::new(&bytes).expect("an MCAP file") {
        let message = message.expect("a message");
        assert_eq!(message.channel.message_encoding, "json");
        let event = FeedEvent::from_payload(&message.channel.topic, &message.data).expect("a record of the feed");
        assert_eq!(event.channel(), message.channel.topic);
        *recorded.entry(message.channel.topic.clone()).or_default() += 1;
    }
    let published: BTreeMap<String, u64> = CHANNELS
        .iter()
        .filter(|c| counts.of(c) > 0)
        .map(|c| (c.to_string(), counts.of(c)))
        .collect();
    assert_eq!(recorded, published);
    for topic in [
        "/learnpnp/plan",
        "/learnpnp/marking",
        "/learnpnp/choice",
        "/learnpnp/episode",
        "/learnpnp/curve",
    ] {
        assert!(recorded.contains_key(topic), "{topic}");
    }
    let summary = mcap::read::Summary::read(&bytes)
        .expect("a summary")
        .expect("the file has one");
    assert!(!summary.chunk_indexes.is_empty());
    assert!(summary.chunk_indexes.iter().all(|c| c.compression.is_empty()));
    // A view replaying the recording serves it to its page.
    let replay = View::start(ViewOptions {
        address: loopback_any_port(),
        replay: Some(file.clone()),
        ..ViewOptions::default()
    })
    .expect("the view starts");
    let (status, served) = http_get(replay.address().expect("served"), "/recording.mcap");
    assert_eq!((status.as_str(), served == bytes), ("HTTP/1.1 200 OK", true));
    replay.close().expect("the view closes");
    let _ = std::fs::remove_dir_all(file.parent().expect("a directory"));
}

#[test]
fn pnp_monitor_lines_follow_the_connection_observer_format() {
    let view = Arc::new(
        View::start(ViewOptions {
            pnp_monitor: loopback_any_port(),
            ..ViewOptions::default()
        })
        .expect("the view starts"),
    );
    let address = view.pnp_monitor_address().expect("the monitor is served");
    let client = TcpStream::connect(address).expect("the monitor accepts");
    client
        .set_read_timeout(Some(Duration::from_secs(30)))
        .expect("a timeout");
    // The client is taken by the view's runtime: wait until it is, then run.
    std::thread::sleep(Duration::from_millis(200));
    let spec = grid(2_000);
    let plan = spec.domain.load_plan().expect("the plan").expect("a plan");
    run_watched(&spec, &view);
    let mut lines = BufReader::new(client).lines();
    let line = lines.next().expect("a line").expect("text");
    let name = plan.name();
    let counts = line
        .strip_prefix(&format!("{name}["))
        .and_then(|rest| rest.strip_suffix(']'))
        .unwrap_or_else(|| panic!("`{line}` is not `{name}[n1,n2,...]`"));
    let counts: Vec<u32> = counts.split(',').map(|n| n.parse().expect("a count")).collect();
    assert_eq!(counts.len(), plan.net().places().len());
    // The first marking sampled is the initial one, in node-id order.
    let mut order: Vec<usize> = (0..plan.net().places().len()).collect();
    order.sort_by(|&a, &b| plan.net().places()[a].id.cmp(&plan.net().places()[b].id));
    let initial = plan.initial_marking();
    let expected: Vec<u32> = order.iter().map(|&i| u32::from(initial.tokens()[i])).collect();
    assert_eq!(counts, expected);
    drop(Arc::into_inner(view).expect("the run let go of the view"));
}

/// The sockets this process listens on, from /proc (Linux).
fn listening_addresses() -> Vec<String> {
    let inodes: HashSet<String> = std::fs::read_dir("/proc/self/fd")
        .map(|dir| {
            dir.flatten()
                .filter_map(|fd| std::fs::read_link(fd.path()).ok())
                .filter_map(|link| {
                    let link = link.to_string_lossy().into_owned();
                    link.strip_prefix("socket:[")?.strip_suffix(']').map(str::to_owned)
                })
                .collect()
        })
        .unwrap_or_default();
    let mut found = Vec::new();
    for table in ["/proc/self/net/tcp", "/proc/self/net/tcp6"] {
        let Ok(text) = std::fs::read_to_string(table) else {
            continue;
        };
        for line in text.lines().skip(1) {
            let fields: Vec<&str> = line.split_whitespace().collect();
            // Field 3 is the state (0A: listening), field 9 the inode.
            if fields.len() > 9 && fields[3] == "0A" && inodes.contains(fields[9]) {
                found.push(fields[1].to_owned());
            }
        }
    }
    found
}

#[test]
fn nothing_listens_beyond_loopback_by_default() {
    assert!(learnpnp_view::default_address().ip().is_loopback());
    assert!(learnpnp_view::default_pnp_monitor_address().ip().is_loopback());
    let view = View::start(ViewOptions {
        address: loopback_any_port(),
        pnp_monitor: loopback_any_port(),
        ..ViewOptions::default()
    })
    .expect("the view starts");
    let listening = listening_addresses();
    assert!(
        listening.len() >= 3,
        "the page, the SDK's server and the monitor: {listening:?}"
    );
    // 0100007F is 127.0.0.1 in /proc's byte order; ::1 is 0...01000000.
    for address in &listening {
        let host = address.split(':').next().unwrap_or("");
        assert!(
            host == "0100007F" || host == "00000000000000000000000001000000",
            "listening on {address}"
        );
    }
    view.close().expect("the view closes");
    // A view asked for nothing listens nowhere.
    let quiet = View::start(ViewOptions::default()).expect("the view starts");
    assert_eq!((quiet.address(), quiet.pnp_monitor_address()), (None, None));
    quiet.close().expect("the view closes");
}

/// What a bundle of the page's channel holds of `records` (one agent's
/// markings, choices and episode ends, in order): see `learnpnp_view`'s bundle.
fn sum_up(records: &[&FeedEvent]) -> serde_json::Value {
    let mut part = serde_json::json!({
        "markings": 0, "marking": null, "sub_plan_markings": 0, "sub_plan_marking": null,
        "choices": 0, "latest_choices": [], "episodes": 0, "returns": [], "last_episode": null,
    });
    let mut points: Vec<String> = Vec::new();
    let bump = |part: &mut serde_json::Value, count: &str| {
        part[count] = serde_json::json!(part[count].as_u64().expect("a count") + 1);
    };
    for record in records {
        match record {
            FeedEvent::Marking(m) => {
                part["source"] = serde_json::to_value(&m.source).expect("JSON");
                let (count, latest) = match m.sub_plan {
                    None => ("markings", "marking"),
                    Some(_) => ("sub_plan_markings", "sub_plan_marking"),
                };
                bump(&mut part, count);
                part[latest] = serde_json::to_value(m).expect("JSON");
            }
            FeedEvent::Choice(c) => {
                part["source"] = serde_json::to_value(&c.source).expect("JSON");
                bump(&mut part, "choices");
                let value = serde_json::to_value(c).expect("JSON");
                let latest = part["latest_choices"].as_array_mut().expect("an array");
                match points.iter().position(|p| *p == c.choice_point) {
                    Some(i) => latest[i] = value,
                    None => {
                        points.push(c.choice_point.clone());
                        latest.push(value);
                    }
                }
            }
            FeedEvent::Episode(e) => {
                part["source"] = serde_json::to_value(&e.source).expect("JSON");
                bump(&mut part, "episodes");
                if !e.evaluation {
                    part["returns"]
                        .as_array_mut()
                        .expect("an array")
                        .push(serde_json::json!([e.episode, e.episode_return]));
                }
                part["last_episode"] = serde_json::json!(e.episode);
            }
            _ => unreachable!("only markings, choices and episode ends are summed up"),
        }
    }
    part
}
