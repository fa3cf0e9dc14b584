//! The view's page (crates/view/page) in a real browser: headless Chromium
//! driven over the DevTools protocol (`--remote-debugging-pipe`), its state
//! read from the page's `#state` element and its pixels from screenshots.
//!
//! - Live: `learnpnp experiment --view=127.0.0.1:0`, the page loaded from
//!   it; seconds later (it redraws once a second) it has drawn more
//!   markings and more of the curve, and the places drawn marked are the
//!   last marking's; with `?every=3` it redraws every 3 s, which the
//!   header's "redraw every" shows and changes.
//! - Replay: an MCAP file (built by the test, and one `learnpnp experiment
//!   --record-mcap` wrote), served by the view at `/recording.mcap` and
//!   loaded with `?mcap=/recording.mcap&t=F`, then the slider moved, then
//!   played and paused; the marking drawn is the last one recorded at or
//!   before the time shown, and a paused page asks for no frames.
//!
//! Needs Debian's `chromium` (or the browser named by `LEARNPNP_CHROMIUM`).
//! Without one the tests say so and pass, unless `LEARNPNP_REQUIRE_BROWSER`
//! is set, as `.ci/run` sets it after installing the browser.

use std::io::{BufRead, BufReader, Write};
use std::os::fd::AsRawFd;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

fn browser() -> Option<PathBuf> {
    let found = crate::headless::find();
    if found.is_none() {
        assert!(
            std::env::var_os("LEARNPNP_REQUIRE_BROWSER").is_none(),
            "LEARNPNP_REQUIRE_BROWSER is set but no chromium was found"
        );
        eprintln!("skipped: no chromium on PATH (install Debian's chromium, or set LEARNPNP_CHROMIUM)");
    }
    found
}

/// A headless Chromium and one page of it, driven over the DevTools protocol
/// on a pipe (fd 3 the browser reads, fd 4 it writes; NUL-ended JSON).
struct Browser {
    child: Child,
    to: std::io::PipeWriter,
    from: BufReader<std::io::PipeReader>,
    next: u64,
    session: Option<String>,
    done: Arc<AtomicBool>,
}

impl Browser {
    /// Starts the browser with a fresh profile in `profile`; it is killed
    /// after two minutes whatever happens.
    fn launch(browser: &Path, profile: &Path) -> Browser {
        let (browser_reads, to) = std::io::pipe().expect("a pipe");
        let (from, browser_writes) = std::io::pipe().expect("a pipe");
        let (r, w) = (browser_reads.as_raw_fd(), browser_writes.as_raw_fd());
        let mut command = Command::new(browser);
        command
            .args(crate::headless::FLAGS)
            .arg("--remote-debugging-pipe")
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg("about:blank")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        // SAFETY: the closure only calls async-signal-safe functions (fcntl, dup2)
        // on descriptors the parent keeps open until the child has started.
        unsafe {
            command.pre_exec(move || {
                // Out of the way of 3 and 4 first, then onto them (dup2 clears close-on-exec).
                let (r, w) = (libc::fcntl(r, libc::F_DUPFD, 10), libc::fcntl(w, libc::F_DUPFD, 10));
                if r < 0 || w < 0 || libc::dup2(r, 3) < 0 || libc::dup2(w, 4) < 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        let child = command.spawn().expect("the browser starts");
        drop((browser_reads, browser_writes));
        let done = Arc::new(AtomicBool::new(false));
        let (pid, flag) = (child.id() as libc::pid_t, done.clone());
        std::thread::spawn(move || {
            let start = Instant::now();
            while !flag.load(Ordering::Relaxed) {
                if start.elapsed() > Duration::from_secs(120) {
                    // SAFETY: a plain kill of the browser this test started (not yet reaped).
                    unsafe { libc::kill(pid, libc::SIGKILL) };
                    return;
                }
                std::thread::sleep(Duration::from_millis(100));
            }
        });
        Browser {
            child,
            to,
            from: BufReader::new(from),
            next: 0,
            session: None,
            done,
        }
    }

    /// Calls `method` (on the page once one is open) and returns its result.
    fn call(&mut self, method: &str, params: Value) -> Value {
        self.next += 1;
        let id = self.next;
        let mut message = json!({"id": id, "method": method, "params": params});
        if let Some(session) = &self.session {
            message["sessionId"] = json!(session);
        }
        let mut bytes = serde_json::to_vec(&message).expect("JSON");
        bytes.push(0);
        self.to.write_all(&bytes).expect("the browser reads its pipe");
        loop {
            let mut reply = Vec::new();
            let n = self.from.read_until(0, &mut reply).expect("the browser's pipe");
            assert!(n > 0, "the browser closed its pipe (killed after two minutes?)");
            reply.pop();
            let reply: Value = serde_json::from_slice(&reply).expect("the browser sends JSON");
            if reply["id"] == json!(id) {
                assert!(reply.get("error").is_none(), "{method}: {}", reply["error"]);
                return reply["result"].clone();
            }
        }
    }

    /// Opens `url` in a new page and attaches to it.
    fn open(&mut self, url: &str) {
        self.session = None;
        let target = self.call("Target.createTarget", json!({"url": "about:blank"}));
        let session = self.call(
            "Target.attachToTarget",
            json!({"targetId": target["targetId"], "flatten": true}),
        );
        self.session = Some(session["sessionId"].as_str().expect("a session").to_string());
        self.call(
            "Emulation.setDeviceMetricsOverride",
            json!({"width": 1400, "height": 900, "deviceScaleFactor": 1, "mobile": false}),
        );
        self.call("Page.navigate", json!({"url": url}));
    }

    /// The value of the JavaScript expression `expr` in the page.
    fn eval(&mut self, expr: &str) -> Value {
        let result = self.call(
            "Runtime.evaluate",
            json!({"expression": expr, "returnByValue": true, "awaitPromise": true}),
        );
        assert!(
            result.get("exceptionDetails").is_none(),
            "{expr}: {}",
            result["exceptionDetails"]
        );
        result["result"]["value"].clone()
    }

    /// The page's `#state` attributes (what it shows), as an object.
    fn state(&mut self) -> Value {
        self.eval("document.getElementById('state') ? {...document.getElementById('state').dataset} : null")
    }

    /// Polls the page's state until `ready` holds of it, for up to `within`.
    fn wait_for(&mut self, within: Duration, what: &str, ready: impl Fn(&Value) -> bool) -> Value {
        let start = Instant::now();
        loop {
            let state = self.state();
            if !state.is_null() && ready(&state) {
                return state;
            }
            assert!(
                start.elapsed() < within,
                "{what} within {within:?}; the page shows {state}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// A PNG screenshot of the page.
    fn screenshot(&mut self) -> Vec<u8> {
        let shot = self.call("Page.captureScreenshot", json!({"format": "png"}));
        base64(shot["data"].as_str().expect("base64 data"))
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        self.done.store(true, Ordering::Relaxed);
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let digits: Vec<u8> = text.bytes().filter(|&c| c != b'=').map(value).collect();
    digits
        .chunks(4)
        .flat_map(|q| {
            let n = q
                .iter()
                .enumerate()
                .fold(0u32, |n, (i, &d)| n | u32::from(d) << (18 - 6 * i));
            let bytes = n.to_be_bytes();
            bytes[1..q.len()].to_vec()
        })
        .collect()
}

/// Asserts that the screenshot `png` shows the plan drawn in the page's plan
/// box (`state.planBox`: x, y, width, height): lines and labels on its white,
/// and a marked place's fill.
fn assert_plan_drawn(png: &[u8], state: &Value) {
    let mut reader = png::Decoder::new(std::io::Cursor::new(png)).read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("a size")];
    let info = reader.next_frame(&mut buf).expect("a frame");
    let channels = info.color_type.samples();
    let (w, h) = (info.width as usize, info.height as usize);
    let plan_box: Vec<usize> = state["planBox"]
        .as_str()
        .expect("the plan's box")
        .split(',')
        .map(|v| v.parse().expect("a number"))
        .collect();
    let [x0, y0, bw, bh] = plan_box[..] else {
        panic!("plan box {plan_box:?}")
    };
    assert!(
        bw > 200 && bh > 200 && x0 + bw <= w && y0 + bh <= h,
        "plan box {plan_box:?} in {w} x {h}"
    );
    let (mut ink, mut marked) = (0usize, 0usize);
    for y in y0..y0 + bh {
        for x in x0..x0 + bw {
            let px = &buf[(y * w + x) * channels..][..3];
            if px.iter().any(|&c| c < 200) {
                ink += 1;
            }
            // The marked places' fill, #ffd54a (style.css).
            if px[0].abs_diff(0xff) < 20 && px[1].abs_diff(0xd5) < 20 && px[2].abs_diff(0x4a) < 20 {
                marked += 1;
            }
        }
    }
    let area = bw * bh;
    assert!(ink * 200 > area, "the plan is drawn: {ink} dark pixels of {area}");
    assert!(marked > 100, "a marked place is filled: {marked} pixels");
}

/// One record of an MCAP file (https://mcap.dev/spec): opcode, u64 length, body.
fn record(out: &mut Vec<u8>, op: u8, body: &[u8]) {
    out.push(op);
    out.extend_from_slice(&(body.len() as u64).to_le_bytes());
    out.extend_from_slice(body);
}

fn string(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

const MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// An MCAP file of `messages` (topic, log time in ns, JSON record), the
/// channels and messages in one uncompressed chunk, as a view records them.
fn mcap(messages: &[(&str, u64, Value)]) -> Vec<u8> {
    let mut topics: Vec<&str> = messages.iter().map(|m| m.0).collect();
    topics.sort_unstable();
    topics.dedup();
    let mut chunk = Vec::new();
    for (i, topic) in topics.iter().enumerate() {
        let mut body = Vec::new();
        body.extend_from_slice(&(i as u16 + 1).to_le_bytes());
        body.extend_from_slice(&0u16.to_le_bytes());
        string(&mut body, topic);
        string(&mut body, "json");
        body.extend_from_slice(&0u32.to_le_bytes());
        record(&mut chunk, 0x04, &body);
    }
    for (seq, (topic, time, value)) in messages.iter().enumerate() {
        let channel = topics.iter().position(|t| t == topic).expect("a channel") as u16 + 1;
        let mut body = Vec::new();
        body.extend_from_slice(&channel.to_le_bytes());
        body.extend_from_slice(&(seq as u32).to_le_bytes());
        body.extend_from_slice(&time.to_le_bytes());
        body.extend_from_slice(&time.to_le_bytes());
        body.extend_from_slice(&serde_json::to_vec(value).expect("JSON"));
        record(&mut chunk, 0x05, &body);
    }
    let mut out = MAGIC.to_vec();
    let mut header = Vec::new();
    string(&mut header, "");
    string(&mut header, "learnpnp test");
    record(&mut out, 0x01, &header);
    let mut body = Vec::new();
    body.extend_from_slice(&messages.first().map_or(0, |m| m.1).to_le_bytes());
    body.extend_from_slice(&messages.last().map_or(0, |m| m.1).to_le_bytes());
    body.extend_from_slice(&(chunk.len() as u64).to_le_bytes());
    body.extend_from_slice(&0u32.to_le_bytes());
    string(&mut body, "");
    body.extend_from_slice(&(chunk.len() as u64).to_le_bytes());
    body.extend_from_slice(&chunk);
    record(&mut out, 0x06, &body);
    record(&mut out, 0x0f, &0u32.to_le_bytes());
    record(&mut out, 0x02, &[0; 20]);
    out.extend_from_slice(MAGIC);
    out
}

/// A recording's records: (topic, log time in ns, record), in log-time order.
type Records = Vec<(String, u64, Value)>;

/// Reads an MCAP file's messages (https://mcap.dev/spec), its chunks
/// uncompressed, as a view records them.
fn read_mcap(bytes: &[u8]) -> Records {
    fn u16_at(b: &[u8], at: usize) -> u16 {
        u16::from_le_bytes(b[at..at + 2].try_into().expect("2 bytes"))
    }
    fn u32_at(b: &[u8], at: usize) -> usize {
        u32::from_le_bytes(b[at..at + 4].try_into().expect("4 bytes")) as usize
    }
    fn u64_at(b: &[u8], at: usize) -> u64 {
        u64::from_le_bytes(b[at..at + 8].try_into().expect("8 bytes"))
    }
    fn walk(data: &[u8], channels: &mut Vec<(u16, String)>, out: &mut Records) -> bool {
        let mut at = 0;
        while at + 9 <= data.len() {
            let (op, len) = (data[at], u64_at(data, at + 1) as usize);
            let body = &data[at + 9..at + 9 + len];
            at += 9 + len;
            match op {
                0x04 => {
                    let n = u32_at(body, 4);
                    let topic = String::from_utf8(body[8..8 + n].to_vec()).expect("a topic");
                    channels.push((u16_at(body, 0), topic));
                }
                0x05 => {
                    let id = u16_at(body, 0);
                    let topic = &channels.iter().find(|c| c.0 == id).expect("a known channel").1;
                    let record = serde_json::from_slice(&body[22..]).expect("a JSON record");
                    out.push((topic.clone(), u64_at(body, 6), record));
                }
                0x06 => {
                    let n = u32_at(body, 28);
                    assert_eq!(&body[32..32 + n], b"", "an uncompressed chunk");
                    let size = u64_at(body, 32 + n) as usize;
                    walk(&body[40 + n..40 + n + size], channels, out);
                }
                0x02 => return true,
                _ => {}
            }
        }
        false
    }
    assert!(bytes.starts_with(MAGIC), "an MCAP file");
    let (mut channels, mut out) = (Vec::new(), Vec::new());
    assert!(walk(&bytes[MAGIC.len()..], &mut channels, &mut out), "a footer");
    out.sort_by_key(|m| m.1);
    out
}

/// The agent `run/agent` a record comes from.
fn agent_of(record: &Value) -> String {
    format!("{}/{}", record["source"]["run"], record["source"]["agent"])
}

/// The marked places of a MarkingSample as the page reports them drawn:
/// `[[label, tokens], ...]` in place-id order, with the labels of its plan.
fn marked(sample: &Value, records: &Records) -> Value {
    let agent = agent_of(sample);
    let plan = records
        .iter()
        .find(|(topic, _, r)| topic == "/learnpnp/plan" && agent_of(r) == agent)
        .map(|(_, _, plan)| plan)
        .expect("the agent's plan");
    let label = |id: usize| {
        plan["places"]
            .as_array()
            .expect("places")
            .iter()
            .find(|p| p["id"] == json!(id))
            .map(|p| p["label"].clone())
            .expect("a place of the plan")
    };
    let tokens = sample["tokens"].as_array().expect("tokens");
    Value::Array(
        tokens
            .iter()
            .enumerate()
            .filter(|(_, n)| n.as_u64() != Some(0))
            .map(|(id, n)| json!([label(id), n]))
            .collect(),
    )
}

/// A fresh temporary directory for the test `name` (emptied if it was there).
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("learnpnp-view-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    dir
}

/// SplitMix64 (Steele, Lea and Flood 2014): the test's own seeded numbers.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

/// A recorded run of a small plan with a choice point (seeded, so the same
/// file every time): its plan, then per episode its markings (and its
/// sub-plan `go`'s), its choice, its end, and a curve point every fifth episode.
fn recording() -> Vec<(&'static str, u64, Value)> {
    let places = ["init", "choose", "go.exec", "wait.exec", "goal"];
    let source = json!({"run": 0, "agent": 0});
    let plan = json!({
        "source": source, "plan": "test",
        "places": places.iter().enumerate().map(|(id, label)| json!({"id": id, "label": label})).collect::<Vec<_>>(),
        "transitions": [
            {"id": 0, "label": "start", "inputs": [0], "outputs": [1]},
            {"id": 1, "label": "go.start", "inputs": [1], "outputs": [2]},
            {"id": 2, "label": "wait.start", "inputs": [1], "outputs": [3]},
            {"id": 3, "label": "go.end", "inputs": [2], "outputs": [4]},
            {"id": 4, "label": "wait.end", "inputs": [3], "outputs": [1]},
        ],
    });
    let mut rng = SplitMix(40);
    let t0 = 1_764_800_000_000_000_000u64;
    let mut t = t0;
    let mut messages = vec![("/learnpnp/plan", t, plan)];
    let mut values = [0.0f64, 0.0];
    let mut updates = [0u64, 0];
    for episode in 0..30u64 {
        let mut step = 0u64;
        let mut at = 0usize;
        let mut ret = 0.0;
        while at != 4 {
            let mut tokens = vec![0u32; places.len()];
            tokens[at] = 1;
            t += 5_000_000 + rng.next() % 35_000_000;
            let running: Vec<&str> = match at {
                2 => vec!["go"],
                3 => vec!["wait"],
                _ => vec![],
            };
            messages.push((
                "/learnpnp/marking",
                t,
                json!({"source": source, "episode": episode, "step": step,
                       "tokens": tokens, "marked": [{"label": places[at], "tokens": 1}], "running": running}),
            ));
            if at == 2 {
                // The action `go` is a sub-plan: its marking too, which the page does not draw.
                t += 1;
                messages.push((
                    "/learnpnp/marking",
                    t,
                    json!({"source": source, "sub_plan": "go", "episode": episode, "step": step,
                           "tokens": [0, 1], "marked": [{"label": "stepping", "tokens": 1}], "running": ["step"]}),
                ));
            }
            at = match at {
                0 => 1,
                1 => {
                    let greedy = usize::from(values[1] > values[0]);
                    let explore = rng.next() % 10 < 3;
                    let taken = if explore { 1 - greedy } else { greedy };
                    t += 1;
                    messages.push((
                        "/learnpnp/choice",
                        t,
                        json!({"source": source, "episode": episode, "step": step, "choice_point": "choose",
                               "options": [
                                   {"label": "go.start", "value": (updates[0] > 0).then_some(values[0]), "updates": updates[0]},
                                   {"label": "wait.start", "value": (updates[1] > 0).then_some(values[1]), "updates": updates[1]}],
                               "taken": taken, "greedy": greedy, "explored": taken != greedy}),
                    ));
                    let reward = if taken == 0 { 1.0 } else { -0.1 };
                    ret += reward;
                    updates[taken] += 1;
                    values[taken] += 0.2 * (reward - values[taken]);
                    2 + taken
                }
                2 => 4,
                _ => 1,
            };
            step += 1;
        }
        t += 1;
        messages.push((
            "/learnpnp/episode",
            t,
            json!({"source": source, "episode": episode, "episode_return": ret, "evaluation": false}),
        ));
        if episode % 5 == 4 {
            messages.push((
                "/learnpnp/curve",
                t,
                json!({"run": 0, "episode": episode + 1, "value": values[0]}),
            ));
        }
    }
    messages
}

/// Loads `file` (whose records are `records`) in the page with `?t=0.5`,
/// moves the slider back and forth, plays and pauses it: each time the places
/// drawn marked are those of the last marking recorded at or before the time
/// shown, for the agent shown.
fn assert_replays(browser: &Path, dir: &Path, file: Vec<u8>, records: &Records) {
    let first = records[0].1;
    let span = records.last().expect("records").1 - first;
    // The view's server, serving the page and the recording at /recording.mcap.
    let path = dir.join("replayed.mcap");
    std::fs::write(&path, file).expect("the recording written");
    let view = learnpnp_view::View::start(learnpnp_view::ViewOptions {
        address: Some("127.0.0.1:0".parse().expect("an address")),
        replay: Some(path),
        ..learnpnp_view::ViewOptions::default()
    })
    .expect("the view starts");
    let address = view.address().expect("the view's address");
    let mut page = Browser::launch(browser, &dir.join("profile"));
    let check = |state: &Value, what: &str| {
        let t_ns: u64 = state["tNs"]
            .as_str()
            .and_then(|t| t.parse().ok())
            .expect("the time shown");
        let agent = state["agent"].as_str().expect("the agent shown");
        let by_then = |sub_plan: bool| {
            records.iter().rfind(|(topic, time, r)| {
                topic == "/learnpnp/marking"
                    && time - first <= t_ns
                    && agent_of(r) == agent
                    && r.get("sub_plan").is_some() == sub_plan
            })
        };
        let sample = by_then(false).map(|(_, _, sample)| sample).expect("a marking by then");
        // A sub-plan's marking is shown on its own line, never drawn on the plan.
        let sub_plan = by_then(true).map_or_else(
            || "-".to_string(),
            |(_, _, r)| {
                format!(
                    "{}: {}",
                    r["sub_plan"].as_str().expect("a name"),
                    r["marked"][0]["label"].as_str().expect("a label")
                )
            },
        );
        assert_eq!(
            state["subPlan"],
            json!(sub_plan),
            "{what}: the sub-plan's marking at {t_ns} ns"
        );
        let shown: Value = serde_json::from_str(state["marked"].as_str().expect("the marked places")).expect("JSON");
        assert_eq!(
            shown,
            marked(sample, records),
            "{what}: the places drawn marked at {t_ns} ns"
        );
        let last: Value =
            serde_json::from_str(state["lastMarking"].as_str().expect("the marking shown")).expect("JSON");
        assert_eq!(&last, sample, "{what}: the marking shown at {t_ns} ns");
        assert_eq!(state["step"], json!(sample["step"].to_string()), "{what}");
        t_ns
    };

    page.open(&format!("http://{address}/?mcap=/recording.mcap&t=0.5"));
    let state = page.wait_for(Duration::from_secs(20), "the recording loaded", |s| {
        s["mode"] == "replay" && !s["tNs"].as_str().unwrap_or("").is_empty() || s["error"] != ""
    });
    assert_eq!(state["error"], "", "{state}");
    assert_eq!(
        page.eval("document.getElementById('every-control').hidden"),
        json!(true),
        "no live redraw period while replaying"
    );
    assert_eq!(state["spanNs"], json!(span.to_string()));
    let t = check(&state, "t=0.5");
    assert!(t.abs_diff(span / 2) <= 1, "t=0.5 shows {t} ns of {span}");
    let markings = |sub_plan: bool| {
        records
            .iter()
            .filter(|m| m.0 == "/learnpnp/marking" && m.1 - first <= t && m.2.get("sub_plan").is_some() == sub_plan)
            .count()
    };
    assert_eq!(state["markings"], json!(markings(false).to_string()));
    assert_eq!(state["subPlanMarkings"], json!(markings(true).to_string()));
    let shot = page.screenshot();
    assert_plan_drawn(&shot, &state);

    // The slider moved back to a fifth and forward to nine tenths, as a user drags it.
    for (at, what) in [(200, "slider at 0.2"), (900, "slider at 0.9")] {
        page.eval(&format!(
            "(() => {{ const s = document.getElementById('slider'); s.value = '{at}'; \
             s.dispatchEvent(new Event('input')); }})()"
        ));
        let want = span * at / 1000;
        let state = page.wait_for(Duration::from_secs(10), what, |s| {
            s["tNs"]
                .as_str()
                .and_then(|t| t.parse::<u64>().ok())
                .is_some_and(|t| t.abs_diff(want) <= 1)
        });
        check(&state, what);
    }

    // Played from the start at the fastest speed that lasts two seconds (or
    // the slowest), paused on the way (if it has not ended): the marking shown
    // is the one recorded at the time shown.
    let speed = ["10", "5", "2", "1"]
        .into_iter()
        .find(|s| span / s.parse::<u64>().expect("a speed") >= 2_000_000_000)
        .unwrap_or("0.5");
    page.eval(&format!(
        "document.getElementById('speed').value = '{speed}'; \
         document.getElementById('speed').dispatchEvent(new Event('change')); \
         document.getElementById('slider').value = '0'; \
         document.getElementById('slider').dispatchEvent(new Event('input'))"
    ));
    page.wait_for(Duration::from_secs(10), "back at the start", |s| s["tNs"] == "0");
    page.eval("document.getElementById('play').click()");
    page.wait_for(Duration::from_secs(20), "playing", |s| {
        s["tNs"]
            .as_str()
            .and_then(|t| t.parse::<u64>().ok())
            .is_some_and(|t| t > span / 10)
    });
    page.eval("document.getElementById('play').textContent === 'pause' && document.getElementById('play').click()");
    let paused =
        page.eval("new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(() => done(true))))");
    assert_eq!(paused, json!(true));
    let state = page.state();
    check(&state, "paused after playing");

    // Paused (and its last redraw done), the page asks for no frames and runs
    // no timers: it does not spin.
    std::thread::sleep(Duration::from_millis(500));
    let idle = page.eval(
        "new Promise((done) => { let frames = 0; let timers = 0; \
           const raf = window.requestAnimationFrame; const st = window.setTimeout; \
           window.requestAnimationFrame = (f) => { frames += 1; return raf(f); }; \
           window.setTimeout = (f, t) => { timers += 1; return st(f, t); }; \
           st(() => { window.requestAnimationFrame = raf; window.setTimeout = st; done([frames, timers]); }, 1000); })",
    );
    assert_eq!(idle, json!([0, 0]), "frames and timers asked for in a second, paused");
    drop(page);
    view.close().expect("the view closes");
}

#[test]
fn a_recording_replays_at_the_time_asked_and_where_the_slider_is_moved() {
    let Some(browser) = browser() else { return };
    let dir = scratch("replay");
    let messages = recording();
    let file = mcap(&messages);
    let records = read_mcap(&file);
    assert_eq!(records.len(), messages.len(), "the test's writer and reader agree");
    assert_replays(&browser, &dir, file, &records);
    let _ = std::fs::remove_dir_all(&dir);
}

/// One Soft-SoSMC run of Keepaway's pass decisions, the runs these tests watch.
const ONE_PASS_RUN: [&str; 6] = ["experiment", "keepaway-pass", "--algo", "soft-sosmc", "--runs", "1"];

#[test]
fn a_run_recorded_by_learnpnp_experiment_replays() {
    let Some(browser) = browser() else { return };
    let dir = scratch("recorded");
    let file = dir.join("run.mcap");
    let out = Command::new(env!("CARGO_BIN_EXE_learnpnp"))
        .args(ONE_PASS_RUN)
        .args(["--episodes", "30"])
        .args(["--eval-every", "10", "--eval-episodes", "1", "--threads", "1", "--out"])
        .arg(dir.join("out"))
        .arg("--record-mcap")
        .arg(&file)
        .output()
        .expect("the learnpnp command runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let bytes = std::fs::read(&file).expect("the recording");
    let records = read_mcap(&bytes);
    assert!(
        records.iter().filter(|r| r.0 == "/learnpnp/marking").count() >= 3,
        "a few markings recorded"
    );
    assert_replays(&browser, &dir, bytes, &records);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `learnpnp experiment` running with its view on a free loopback port;
/// killed when dropped.
struct Run {
    child: Child,
    address: String,
}

impl Run {
    /// Starts `learnpnp experiment ARGS --view=127.0.0.1:0` and waits for the
    /// address it says the view is served on.
    fn start(args: &[&str]) -> Run {
        let mut child = Command::new(env!("CARGO_BIN_EXE_learnpnp"))
            .args(args)
            .arg("--view=127.0.0.1:0")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the learnpnp command starts");
        let stderr = child.stderr.take().expect("its standard error");
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if let Some(rest) = line.strip_prefix("view: http://") {
                    let _ = tx.send(rest.split('/').next().unwrap_or_default().to_string());
                }
            }
        });
        let address = match rx.recv_timeout(Duration::from_secs(60)) {
            Ok(address) => address,
            Err(e) => {
                let _ = child.kill();
                let status = child.wait();
                panic!("the view's address was not printed within a minute ({e}); the run: {status:?}");
            }
        };
        Run { child, address }
    }
}

impl Drop for Run {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn number(state: &Value, key: &str) -> u64 {
    state[key]
        .as_str()
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{key} in {state}"))
}

#[test]
fn a_live_run_is_drawn_as_it_learns() {
    let Some(browser) = browser() else { return };
    let dir = scratch("live");
    let out = dir.join("out");
    let run = Run::start(
        &[
            &ONE_PASS_RUN[..],
            &[
                "--episodes",
                "100000",
                "--eval-every",
                "20",
                "--eval-episodes",
                "1",
                "--threads",
                "1",
                "--out",
                out.to_str().expect("a path"),
            ],
        ]
        .concat(),
    );
    let mut page = Browser::launch(&browser, &dir.join("profile"));
    page.open(&format!("http://{}/", run.address));
    let grown = |s: &Value| number(s, "markings") > 0 && number(s, "curvePoints") > 0 && s["marked"] != "";
    let first = page.wait_for(Duration::from_secs(30), "a marking and a curve point", grown);
    // The page redraws live once a second: two and a half seconds hold two redraws.
    std::thread::sleep(Duration::from_millis(2500));
    let second = page.state();
    assert!(
        number(&second, "markings") > number(&first, "markings"),
        "more markings later: {first} then {second}"
    );
    assert!(
        number(&second, "curvePoints") > number(&first, "curvePoints"),
        "more curve points later: {first} then {second}"
    );
    // The places drawn marked are those of the last marking the page received.
    let sample: Value = serde_json::from_str(second["lastMarking"].as_str().expect("the last marking")).expect("JSON");
    let drawn: Value = serde_json::from_str(second["marked"].as_str().expect("the places drawn marked")).expect("JSON");
    let mut drawn: Vec<(String, u64)> = drawn
        .as_array()
        .expect("a list")
        .iter()
        .map(|p| {
            (
                p[0].as_str().expect("a label").to_string(),
                p[1].as_u64().expect("a count"),
            )
        })
        .collect();
    let mut recorded: Vec<(String, u64)> = sample["marked"]
        .as_array()
        .expect("marked places")
        .iter()
        .map(|p| {
            (
                p["label"].as_str().expect("a label").to_string(),
                p["tokens"].as_u64().expect("a count"),
            )
        })
        .collect();
    drawn.sort();
    recorded.sort();
    assert!(!drawn.is_empty(), "a place is marked");
    assert_eq!(drawn, recorded, "the places drawn marked, and the last marking's");

    let shot = page.screenshot();
    assert_plan_drawn(&shot, &second);
    if let Some(path) = std::env::var_os("LEARNPNP_VIEW_SCREENSHOT") {
        std::fs::write(path, &shot).expect("the screenshot saved");
    }

    // `?every=3`: redrawn every 3 s, so 6.5 s watched hold at most three
    // redraws (and once a second, six or seven).
    page.open(&format!("http://{}/?every=3", run.address));
    page.wait_for(Duration::from_secs(30), "a marking and a curve point", grown);
    let mut shown = std::collections::BTreeSet::new();
    let watched = Instant::now();
    while watched.elapsed() < Duration::from_millis(6500) {
        shown.insert(number(&page.state(), "markings"));
        std::thread::sleep(Duration::from_millis(100));
    }
    assert!(
        (2..=4).contains(&shown.len()),
        "with ?every=3, 6.5 s show two to four redraws' counts: {shown:?}"
    );
    // The header's "redraw every" shows it, and picking another period keeps it in the address.
    assert_eq!(page.eval("document.getElementById('every').value"), json!("3"));
    page.eval("const e = document.getElementById('every'); e.value = '2'; e.dispatchEvent(new Event('change')); 1");
    assert_eq!(page.eval("location.search"), json!("?every=2"));
    drop(page);
    drop(run);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The topic a Foxglove panel reads: a message path's topic, before its
/// first field or filter.
fn topic_of(path: &str) -> &str {
    let end = path[1..].find(['.', '{', '[']).map_or(path.len(), |i| i + 1);
    &path[..end]
}

#[test]
fn the_foxglove_layout_reads_the_feeds_channels_and_places_every_panel() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/foxglove-layout.json"))
        .expect("docs/foxglove-layout.json");
    let layout: Value = serde_json::from_str(&text).expect("the layout is JSON");
    let panels = layout["configById"].as_object().expect("configById");
    let channels = learnpnp::feed::CHANNELS;
    for (id, config) in panels {
        let paths: Vec<&str> = match config["paths"].as_array() {
            Some(paths) => paths.iter().map(|p| p["value"].as_str().expect("a path")).collect(),
            None => vec![config["topicPath"].as_str().expect("a topic path")],
        };
        for path in paths {
            assert!(
                channels.contains(&topic_of(path)),
                "{id} reads {path}, not a channel of the feed"
            );
        }
    }
    // The mosaic's leaves are exactly the configured panels.
    fn leaves<'a>(node: &'a Value, out: &mut Vec<&'a str>) {
        match node {
            Value::String(id) => out.push(id),
            _ => {
                leaves(&node["first"], out);
                leaves(&node["second"], out);
            }
        }
    }
    let mut placed = Vec::new();
    leaves(&layout["layout"], &mut placed);
    placed.sort_unstable();
    let mut configured: Vec<&str> = panels.keys().map(String::as_str).collect();
    configured.sort_unstable();
    assert_eq!(placed, configured);
}
