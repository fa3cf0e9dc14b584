//! Recording Keepaway episodes as RoboCup game logs: the format rcssserver
//! writes (log version 5), the keepers' notes, and results untouched by recording.

use crate::util::run_quietly;
use std::sync::Arc;

use learnpnp::domains::keepaway::{KeepawayDomainConfig, KeepawayMode, KeepawayTask};
use learnpnp::experiment::options::DomainName;
use learnpnp_flags::args::parse_experiment_flags;

use learnpnp::learning::{EpisodeMode, Learner, RandomLearner};
use learnpnp::rng::seeded;
use learnpnp_keepaway::rcg::{GameLog, MAX_PLAYER};

fn recorded(mode: KeepawayMode, seed: u64) -> String {
    let config = KeepawayDomainConfig::for_mode(mode);
    let plan = config.default_plan().expect("the plan loads").map(Arc::new);
    let mut learner = |k: usize| Box::new(RandomLearner::new(seeded(seed + k as u64))) as Box<dyn Learner>;
    let mut task = KeepawayTask::new(config, plan, &mut learner, seeded(seed)).expect("a task");
    task.record_episode(EpisodeMode::Evaluate).expect("an episode").1
}

/// The top-level elements of an s-expression line, as text.
fn elements(line: &str) -> Vec<&str> {
    let inner = line
        .strip_prefix('(')
        .and_then(|l| l.strip_suffix(')'))
        .expect("a list");
    let mut out = Vec::new();
    let (mut depth, mut start) = (0, None);
    for (i, c) in inner.char_indices() {
        match c {
            '(' => {
                if depth == 0 {
                    start = Some(i);
                }
                depth += 1;
            }
            ')' => {
                depth -= 1;
                if depth == 0 {
                    out.push(&inner[start.take().expect("an open list")..=i]);
                }
            }
            ' ' if depth == 0 => {
                if let Some(s) = start.take() {
                    out.push(&inner[s..i]);
                }
            }
            _ if depth == 0 && start.is_none() => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push(&inner[s..]);
    }
    out
}

#[test]
fn a_recorded_episode_has_the_servers_log_format() {
    let text = recorded(KeepawayMode::Pass, 7);
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("ULG5"));
    let server = lines.next().expect("server_param");
    assert!(server.starts_with("(server_param (") && server.contains("(keepaway 1)"));
    assert!(server.contains("(keepaway_length 20)(keepaway_width 20)"));
    assert!(lines.next().expect("player_type").starts_with("(player_type (id 0)"));
    assert_eq!(lines.next(), Some("(playmode 0 play_on)"));
    assert_eq!(lines.next(), Some("(team 0 keepers takers 0 0)"));
    let shows: Vec<&str> = text.lines().filter(|l| l.starts_with("(show ")).collect();
    for (cycle, show) in shows.iter().enumerate() {
        let parts = elements(show);
        assert_eq!(parts[0], "show");
        assert_eq!(parts[1], cycle.to_string(), "shows are consecutive cycles from 0");
        let ball = elements(parts[2]);
        assert_eq!(ball[0], "(b)", "{}", parts[2]);
        assert_eq!(ball.len(), 5, "(b) x y vx vy: {}", parts[2]);
        // All 22 players, left 1..11 then right 1..11, as rcssmonitor requires.
        assert_eq!(parts.len(), 3 + 2 * MAX_PLAYER, "cycle {cycle}");
        for (i, player) in parts[3..].iter().enumerate() {
            let (side, unum) = if i < MAX_PLAYER {
                ('l', i + 1)
            } else {
                ('r', i + 1 - MAX_PLAYER)
            };
            let fields = elements(player);
            assert_eq!(fields[0], format!("({side} {unum})"));
            assert_eq!(fields[1], "0", "player type");
            let enabled = if side == 'l' { unum <= 3 } else { unum <= 2 };
            assert_eq!(fields[2] != "0", enabled, "{player}");
            if enabled {
                let state = u32::from_str_radix(fields[2].trim_start_matches("0x"), 16).expect("hex state");
                assert_eq!(state & 1, 1, "enabled players stand: {player}");
            } else {
                let x: f64 = fields[3].parse().expect("x");
                let sign = if side == 'l' { -1.0 } else { 1.0 };
                assert_eq!(x, sign * 3.0 * unum as f64, "the bench: {player}");
                assert_eq!(fields[4], "-37");
            }
            for f in &fields[3..9] {
                f.parse::<f64>().unwrap_or_else(|_| panic!("a number: {f} in {player}"));
            }
            assert!(fields[9].starts_with("(v h "), "{player}");
            assert_eq!(
                fields[10].split(' ').count(),
                5,
                "(s stamina effort recovery capacity): {player}"
            );
            assert_eq!(fields[11].split(' ').count(), 12, "(c and 11 counts): {player}");
        }
    }
    let log = GameLog::parse(&text).expect("the log reads back");
    assert_eq!(log.frames.len(), shows.len());
    assert_eq!(log.keepaway, Some([20.0, 20.0]));
    assert_eq!(log.teams, ["keepers".to_string(), "takers".to_string()]);
    assert!(log.frames.iter().all(|f| f.players.len() == 5));
    let last = log.frames.last().expect("a show");
    let out = last.ball[0].abs() >= 10.0 || last.ball[1].abs() >= 10.0;
    let end = log.messages.last().expect("the end message");
    assert!(
        end.text
            .starts_with(&format!("episode over after {} cycles", last.time))
    );
    assert_eq!(out, end.text.contains("the ball left the region"), "{}", end.text);
    // Only keeper 1 follows a plan in the pass experiment.
    assert!(!log.notes.is_empty());
    assert!(log.notes.iter().all(|n| n.note.keeper == 1));
    let choice = log.notes.iter().find_map(|n| n.note.choice.as_ref()).expect("a choice");
    assert!(choice.options.len() >= 2);
    assert!(choice.options.iter().all(|o| o.name.ends_with(".start")), "{choice:?}");
}

#[test]
fn every_keeper_following_a_plan_has_notes() {
    let log = GameLog::parse(&recorded(KeepawayMode::Position, 3)).expect("a log");
    for k in 1..=3 {
        assert!(log.notes.iter().any(|n| n.note.keeper == k), "keeper {k}");
    }
}

#[test]
fn recording_changes_no_result() {
    let args = [
        "--algo",
        "soft-sosmc",
        "--runs",
        "2",
        "--episodes",
        "30",
        "--eval-every",
        "15",
        "--eval-episodes",
        "2",
        "--greedy-episodes",
        "2",
    ];
    let plain = parse_experiment_flags(&args)
        .expect("valid flags")
        .spec(DomainName::KeepawayPass)
        .expect("a spec");
    let mut with_record = args.to_vec();
    with_record.extend(["--record", "2"]);
    let recording = parse_experiment_flags(&with_record)
        .expect("valid flags")
        .spec(DomainName::KeepawayPass)
        .expect("a spec");
    assert_eq!(recording.domain.replays(), 2);
    let a = run_quietly(&plain, 1);
    let b = run_quietly(&recording, 2);
    for (x, y) in a.runs.iter().zip(&b.runs) {
        assert_eq!(x.evals, y.evals);
        assert_eq!(x.greedy, y.greedy);
        assert_eq!(x.values, y.values);
    }
    assert!(a.runs[0].replays.is_empty());
    assert_eq!(b.runs[0].replays.len(), 2);
    assert!(b.runs[1].replays.is_empty(), "only run 0 records");
    assert_ne!(b.runs[0].replays[0], b.runs[0].replays[1]);

    let refused = parse_experiment_flags(&["--algo", "sarsa0", "--record", "1"])
        .expect("valid flags")
        .spec(DomainName::ParrRussell);
    assert!(refused.is_err_and(|e| e.to_string().contains("--record")));
}

#[test]
fn logs_of_the_server_read_and_errors_name_the_line_and_token() {
    // Lines as rcssserver writes them (log version 6 with a focus point and
    // the team in the show, as monitor protocol 5 does), other lines skipped.
    let server = "ULG6\n\
        (server_param (goal_width 14.02)(keepaway 1)(keepaway_length 20)(keepaway_width 20)(simulator_step 100))\n\
        (player_param (player_types 18))\n\
        (player_type (id 0)(player_speed_max 1.05))\n\
        (playmode 0 play_on)\n\
        (team 0 keepers takers 0 0)\n\
        (msg 1 1 \"(referee training Keepaway 1)\")\n\
        (show 1 (pm 3) (tm keepers takers 0 0) ((b) -6 -6 0 0) ((l 1) 0 0x1 -9.1 -8.2 0 0 45 0 (v h 90) (fp 0 0) (s 8000 1 1 130600) (f l 2) (c 0 1 2 0 0 0 0 0 0 0 0 0)) \
        ((l 2) 0 0 -6 -37 0 0 0 0 (v h 90) (s 8000 1 1 130600) (c 0 0 0 0 0 0 0 0 0 0 0)))\n";
    let log = GameLog::parse(server).expect("the server's lines read");
    assert_eq!(log.version, 6);
    assert_eq!(log.frames.len(), 1);
    assert_eq!(log.frames[0].players.len(), 1, "disabled players are left out");
    assert_eq!(log.frames[0].players[0].x, -9.1);
    assert_eq!(log.messages[0].text, "(referee training Keepaway 1)");

    let broken = "ULG5\n(playmode 0 play_on)\n(show 3 ((b) -6 zz 0 0))\n";
    let e = GameLog::parse(broken).expect_err("a broken show");
    assert_eq!(e.line, 3);
    assert_eq!(e.token, "zz");
    assert!(e.to_string().starts_with("line 3: expected the ball's y"), "{e}");

    for (text, line, what) in [
        ("", 1, "empty file"),
        ("ULG3\n", 1, "unsupported"),
        ("<html>\n", 1, "not a text game log"),
        ("ULG5\n(show 1 ((b) 0 0 0 0)\n", 2, "unbalanced"),
        ("ULG5\n(msg 1 2 \"learnpnp keeper=x\")\n", 2, "malformed keeper note"),
        ("ULG5\n(playmode 0 play_on)\n", 2, "no show"),
    ] {
        let e = GameLog::parse(text).expect_err(text);
        assert_eq!(e.line, line, "{text}: {e}");
        assert!(e.to_string().contains(what), "{text}: {e}");
    }
}
