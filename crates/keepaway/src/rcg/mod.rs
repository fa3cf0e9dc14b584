//! RoboCup soccer simulator game logs (`.rcg`): the text format of log
//! version 5 (`ULG5`), which rcssserver writes and rcssmonitor and
//! rcsslogplayer replay.
//!
//! A file is a header line `ULG5` followed by one s-expression per line:
//! `(server_param ...)`, `(player_param ...)`, `(player_type ...)`, then
//! `(playmode T mode)`, `(team T left right score_l score_r)`,
//! `(msg T board "text")` and one `(show T ((b) x y vx vy) player...)` per
//! cycle. As in rcssserver's `DispSenderLoggerV4` with the monitor
//! serializer of version 4, a show lists all 22 players, those not in the game
//! with state 0 at the server's bench position `(-3 unum * side, -37)`; an
//! enabled player is
//! `((side unum) type state x y vx vy body neck (v h 90) (s stamina effort recovery capacity) (c counts...))`.
//! Coordinates are the server's (the simulator uses the same numbers).
//!
//! Keepers are the left team `keepers`, takers the right team `takers`, as the
//! keepaway framework names them. Where a plan-driven keeper decides, its
//! current action and last choice are written as a message on the log board,
//! `(msg T 2 "learnpnp keeper=1|action=...|...")` ([`KeeperNote`](crate::rcg::KeeperNote)); monitors
//! list messages, [`GameLog::parse`](crate::rcg::GameLog::parse) reads them back.
//!
//! [`GameLogWriter`](crate::rcg::GameLogWriter) writes one episode (`writer`); [`GameLog::parse`](crate::rcg::GameLog::parse) reads text
//! logs of versions 4 to 6, from this writer or from rcssserver (`parser`); the
//! keepers' notes have their own codec (`note`).

mod note;
mod parser;
mod writer;

pub use note::{ChoiceNote, KeeperNote, OptionNote};
pub use parser::{Frame, GameLog, GameLogFileError, PlayerFrame, RcgError, TimedMessage, TimedNote};
pub use writer::GameLogWriter;

/// The header line of the logs written here.
pub(crate) const HEADER: &str = "ULG5";
/// Players per side in the server (all are listed in every show).
pub const MAX_PLAYER: usize = 11;
/// The keepers' team name (the server's left side).
pub(crate) const KEEPER_TEAM: &str = "keepers";
/// The takers' team name (the server's right side).
pub(crate) const TAKER_TEAM: &str = "takers";
/// The server's message board for referee messages.
const MSG_BOARD: u32 = 1;
/// The server's log board, where keeper notes go.
const LOG_BOARD: u32 = 2;
/// What a keeper note's message starts with.
const NOTE_PREFIX: &str = "learnpnp ";
/// Player state bits of rcssserver (`PlayerState`).
const STATE_STAND: u32 = 0x1;
const STATE_KICK: u32 = 0x2;
const STATE_KICK_FAULT: u32 = 0x4;
/// rcssserver's stamina defaults (v13 and later), shown for every player:
/// keepaway restores stamina at each reset, so it never runs low.
const STAMINA_MAX: f64 = 8000.0;
const STAMINA_CAPACITY: f64 = 130_600.0;
/// The server's default view width (degrees).
const VISIBLE_ANGLE: f64 = 90.0;
/// rcssserver's pitch half width (where the bench row sits 3 m outside).
const PITCH_HALF_WIDTH: f64 = 34.0;

/// A number with at most `decimals` decimals, trailing zeros dropped
/// (rcssserver quantises positions to 0.0001 and angles to 0.001).
fn num(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    };
    if text == "-0" { "0".to_string() } else { text }
}

#[cfg(test)]
mod tests {
    use super::parser::{Sexp, parse_sexp};
    use super::*;

    #[test]
    fn notes_round_trip_through_a_message() {
        let note = KeeperNote {
            keeper: 2,
            action: "Pass1 (to 2)".to_string(),
            choice: Some(ChoiceNote {
                cycle: 40,
                at: "decide|x=1;y%".to_string(),
                options: vec![
                    OptionNote {
                        name: "Hold.start".to_string(),
                        value: 12.5625,
                        visits: 3,
                    },
                    OptionNote {
                        name: "Pass1.start [\"a\"]".to_string(),
                        value: f64::NEG_INFINITY,
                        visits: 0,
                    },
                ],
                chosen: 1,
            }),
        };
        let text = note.to_message();
        assert!(!text.contains('"') && !text.contains(')'), "{text}");
        assert_eq!(KeeperNote::from_message(&text), Ok(Some(note)));
        assert_eq!(KeeperNote::from_message("(referee training Keepaway 1)"), Ok(None));
        assert!(KeeperNote::from_message("learnpnp keeper=x").is_err());
    }

    #[test]
    fn numbers_are_short_and_never_negative_zero() {
        assert_eq!(num(1.5, 4), "1.5");
        assert_eq!(num(-0.00001, 4), "0");
        assert_eq!(num(3.0, 4), "3");
        assert_eq!(num(-2.12345, 4), "-2.1235");
    }

    #[test]
    fn s_expressions_and_their_errors() {
        let s = parse_sexp("(msg 3 1 \"a (b) \"c\"\")").unwrap();
        assert_eq!(
            s,
            Sexp::List(vec![
                Sexp::Atom("msg"),
                Sexp::Atom("3"),
                Sexp::Atom("1"),
                Sexp::Text("a (b) \"c\"")
            ])
        );
        assert!(parse_sexp("(show 1 ((b) 0 0 0 0)").is_err());
        assert!(parse_sexp("(a)) x").is_err());
        assert!(parse_sexp("x (a)").is_err());
    }
}
