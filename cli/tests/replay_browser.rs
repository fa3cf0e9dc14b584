//! A recorded Keepaway episode watched in a real browser: `learnpnp experiment
//! --record` writes a game log, `learnpnp replay` a page, headless Chromium
//! renders it at a chosen cycle, and the players and the ball must be drawn
//! where the log puts them (the page's report in the DOM, and the pixels of a
//! screenshot), with the keepers' notes of that cycle.
//!
//! Needs Debian's `chromium` (or the browser named by `LEARNPNP_CHROMIUM`).
//! Without one the test says so and passes, unless `LEARNPNP_REQUIRE_BROWSER`
//! is set, as `.ci/run` sets it after installing the browser.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use learnpnp_keepaway::rcg::{GameLog, KeeperNote};

use crate::short_experiment;

fn learnpnp(args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_learnpnp"))
        .args(args)
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "learnpnp {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Runs the browser headless on `url` with `extra` flags (a fresh profile,
/// no network of its own), killing it after two minutes.
fn chromium(browser: &Path, profile: &Path, url: &str, extra: &[&str]) -> String {
    let mut child = Command::new(browser)
        .args(crate::headless::FLAGS)
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(url)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("the browser starts");
    let start = Instant::now();
    loop {
        if child.try_wait().expect("the browser can be waited for").is_some() {
            break;
        }
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("the browser did not finish within two minutes");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let out = child.wait_with_output().expect("the browser's output");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The value of attribute `name` of the element with id `id` in a DOM dump.
fn attribute(dom: &str, id: &str, name: &str) -> Option<String> {
    let start = dom.find(&format!("id=\"{id}\""))?;
    let tag_start = dom[..start].rfind('<')?;
    let tag_end = start + dom[start..].find('>')?;
    let tag = &dom[tag_start..tag_end];
    let key = format!("{name}=\"");
    let at = tag.find(&key)? + key.len();
    let value = &tag[at..at + tag[at..].find('"')?];
    Some(
        value
            .replace("&amp;", "&")
            .replace("&quot;", "\"")
            .replace("&gt;", ">")
            .replace("&lt;", "<"),
    )
}

fn numbers(text: &str) -> Vec<f64> {
    text.split(',').map(|v| v.parse().expect("a number")).collect()
}

/// The pixels of a PNG screenshot: width, height, RGB rows.
fn decode(path: &Path) -> (usize, usize, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(path).expect("a screenshot"),
    ));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("a size")];
    let info = reader.next_frame(&mut buf).expect("a frame");
    let channels = info.color_type.samples();
    let (w, h) = (info.width as usize, info.height as usize);
    let mut rgb = Vec::with_capacity(w * h * 3);
    for px in buf[..w * h * channels].chunks(channels) {
        rgb.extend_from_slice(&px[..3]);
    }
    (w, h, rgb)
}

fn colour_at(image: &(usize, usize, Vec<u8>), x: f64, y: f64) -> [u8; 3] {
    let (w, h, rgb) = image;
    let (x, y) = (x.round() as usize, y.round() as usize);
    assert!(x < *w && y < *h, "({x}, {y}) is outside the {w} x {h} screenshot");
    let i = (y * w + x) * 3;
    [rgb[i], rgb[i + 1], rgb[i + 2]]
}

fn close(a: [u8; 3], b: [u8; 3]) -> bool {
    a.iter().zip(b).all(|(&x, y)| x.abs_diff(y) <= 40)
}

const KEEPER: [u8; 3] = [0xf2, 0xd2, 0x1b];
const TAKER: [u8; 3] = [0xd8, 0x34, 0x2c];
const BALL: [u8; 3] = [0xff, 0xff, 0xff];
const FIELD: [u8; 3] = [0x2f, 0x8a, 0x3a];

#[test]
fn a_recorded_episode_is_drawn_where_the_log_puts_it() {
    let Some(browser) = crate::headless::find() else {
        assert!(
            std::env::var_os("LEARNPNP_REQUIRE_BROWSER").is_none(),
            "LEARNPNP_REQUIRE_BROWSER is set but no chromium was found"
        );
        eprintln!("skipped: no chromium on PATH (install Debian's chromium, or set LEARNPNP_CHROMIUM)");
        return;
    };
    let dir = std::env::temp_dir().join(format!("learnpnp-replay-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let out = dir.join("kp");
    let mut args = short_experiment("keepaway-pass", "soft-sosmc", "1", "40");
    args.extend([
        "--eval-every",
        "40",
        "--eval-episodes",
        "1",
        "--greedy-episodes",
        "1",
        "--record",
        "1",
        "--threads",
        "1",
        "--out",
        out.to_str().expect("a path"),
    ]);
    learnpnp(&args);
    let rcg = out.join("replays").join("episode-1.rcg");
    let log = GameLog::read_file(&rcg).expect("the recorded log reads back");
    assert!(log.frames.len() > 20, "a short episode: {} shows", log.frames.len());
    assert!(!log.notes.is_empty(), "the learning keeper's notes are in the log");
    let page = dir.join("episode.html");
    learnpnp(&[
        "replay",
        rcg.to_str().expect("a path"),
        "-o",
        page.to_str().expect("a path"),
    ]);
    let url = |cycle: u32| format!("file://{}#cycle={cycle}", page.display());

    // The page's transform, from a first rendering.
    let dom = chromium(&browser, &dir.join("profile0"), &url(0), &["--dump-dom"]);
    let transform = numbers(&attribute(&dom, "drawn", "data-transform").expect("the page reports its transform"));
    let [scale, ox, oy] = transform[..] else {
        panic!("transform {transform:?}")
    };
    assert!(scale > 10.0, "at least 10 pixels per metre: {scale}");
    let to_px = |x: f64, y: f64| (ox + x * scale, oy + y * scale);

    // A cycle past the start where every object stands clear of the others.
    let clear = |f: &learnpnp_keepaway::rcg::Frame| {
        let mut points = vec![to_px(f.ball[0], f.ball[1])];
        points.extend(f.players.iter().map(|p| to_px(p.x, p.y)));
        points
            .iter()
            .enumerate()
            .all(|(i, a)| points[i + 1..].iter().all(|b| (a.0 - b.0).hypot(a.1 - b.1) > 25.0))
    };
    let frame = log.frames[1..]
        .iter()
        .find(|f| clear(f) && f.players.len() == 5)
        .expect("some cycle with every object apart");
    let cycle = frame.time;

    let dom = chromium(&browser, &dir.join("profile1"), &url(cycle), &["--dump-dom"]);
    assert_eq!(attribute(&dom, "drawn", "data-cycle"), Some(cycle.to_string()));
    let objects = attribute(&dom, "drawn", "data-objects").expect("the page reports what it drew");
    let drawn: Vec<(String, f64, f64)> = objects
        .split(';')
        .map(|o| {
            let (name, at) = o.split_once(':').expect("name:x,y");
            let xy = numbers(at);
            (name.to_string(), xy[0], xy[1])
        })
        .collect();
    let mut expected = vec![("b".to_string(), frame.ball[0], frame.ball[1])];
    expected.extend(
        frame
            .players
            .iter()
            .map(|p| (format!("{}{}", p.side, p.unum), p.x, p.y)),
    );
    assert_eq!(drawn.len(), expected.len(), "{objects}");
    for (name, x, y) in &expected {
        let (px, py) = to_px(*x, *y);
        let (_, dx, dy) = drawn
            .iter()
            .find(|(n, _, _)| n == name)
            .unwrap_or_else(|| panic!("{name} is not drawn: {objects}"));
        assert!(
            (px - dx).abs() < 0.02 && (py - dy).abs() < 0.02,
            "{name} drawn at ({dx}, {dy}), the log puts it at ({px}, {py})"
        );
    }
    // The keepers' notes of that cycle: the last note of each at or before it.
    for k in 1..=3u8 {
        let note: Option<&KeeperNote> = log
            .notes
            .iter()
            .filter(|n| n.time <= cycle && n.note.keeper == k)
            .map(|n| &n.note)
            .next_back();
        let shown = attribute(&dom, &format!("keeper-{k}"), "data-action");
        assert_eq!(
            shown.as_deref(),
            note.map(|n| n.action.as_str()),
            "keeper {k} at cycle {cycle}"
        );
        if let Some(choice) = note.and_then(|n| n.choice.as_ref()) {
            let chosen = attribute(&dom, &format!("keeper-{k}"), "data-chosen");
            assert_eq!(chosen.as_deref(), Some(choice.options[choice.chosen].name.as_str()));
        }
    }

    // The pixels: the ball white at its centre, each player's colour around its centre.
    let shot = dir.join("shot.png");
    chromium(
        &browser,
        &dir.join("profile2"),
        &url(cycle),
        &[&format!("--screenshot={}", shot.display())],
    );
    let image = decode(&shot);
    let canvas = numbers(&attribute(&dom, "drawn", "data-canvas").expect("the canvas position"));
    let on_page = |x: f64, y: f64| {
        let (px, py) = to_px(x, y);
        (canvas[0] + px, canvas[1] + py)
    };
    let (bx, by) = on_page(frame.ball[0], frame.ball[1]);
    assert!(close(colour_at(&image, bx, by), BALL), "the ball at ({bx}, {by})");
    for p in &frame.players {
        let (cx, cy) = on_page(p.x, p.y);
        let colour = if p.side == 'l' { KEEPER } else { TAKER };
        let hits = (0..8)
            .filter(|i| {
                let a = f64::from(*i) * std::f64::consts::FRAC_PI_4 + 0.3;
                close(colour_at(&image, cx + 5.0 * a.cos(), cy + 5.0 * a.sin()), colour)
            })
            .count();
        assert!(
            hits >= 5,
            "{}{} at ({cx}, {cy}): {hits} of 8 pixels in its colour",
            p.side,
            p.unum
        );
    }
    // Far from every object the field is green.
    let spots =
        (0..=38u32).flat_map(|i| (0..=38u32).map(move |j| (f64::from(i) * 0.5 - 9.5, f64::from(j) * 0.5 - 9.5)));
    let (fx, fy) = spots
        .into_iter()
        .find(|&(x, y)| {
            let (px, py) = to_px(x, y);
            expected
                .iter()
                .all(|(_, ex, ey)| (to_px(*ex, *ey).0 - px).hypot(to_px(*ex, *ey).1 - py) > 60.0)
        })
        .expect("an empty spot");
    let (gx, gy) = on_page(fx, fy);
    assert!(close(colour_at(&image, gx, gy), FIELD), "the field at ({gx}, {gy})");
    let _ = std::fs::remove_dir_all(&dir);
}
