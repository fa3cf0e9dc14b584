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
//! `(msg T 2 "learnpnp keeper=1|action=...|...")` ([`KeeperNote`]); monitors
//! list messages, [`GameLog::parse`] reads them back.
//!
//! [`GameLogWriter`] writes one episode; [`GameLog::parse`] reads text logs of
//! versions 4 to 6, from this writer or from rcssserver.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::command::Command;
use super::params::KeepawayConfig;
use super::referee::EndReason;
use super::world::{FieldState, NUM_KEEPERS, NUM_PLAYERS, NUM_TAKERS};

/// The header line of the logs written here.
pub const HEADER: &str = "ULG5";
/// Players per side in the server (all are listed in every show).
pub const MAX_PLAYER: usize = 11;
/// The keepers' team name (the server's left side).
pub const KEEPER_TEAM: &str = "keepers";
/// The takers' team name (the server's right side).
pub const TAKER_TEAM: &str = "takers";
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

/// One option of a keeper's choice: the transitions that lead to it, its
/// learned value and how often that value was updated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OptionNote {
    /// The labels of the transitions that lead to this option (`Pass1.start`).
    pub name: String,
    /// Its value when the keeper chose (negative infinity: no estimate yet).
    pub value: f64,
    /// Updates of that value so far.
    pub visits: u64,
}

/// A keeper's last choice at a choice point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChoiceNote {
    /// The cycle of the choice.
    pub cycle: u32,
    /// Where the plan stood: the labels of its marked places.
    pub at: String,
    /// The options offered.
    pub options: Vec<OptionNote>,
    /// The index of the option taken.
    pub chosen: usize,
}

/// What a plan-driven keeper is doing: its current action and its last choice.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KeeperNote {
    /// The keeper's uniform number (1 to 3).
    pub keeper: u8,
    /// The actions whose execution places are marked (`Hold`, `Pass1`...).
    pub action: String,
    /// The last choice made this episode, if any.
    pub choice: Option<ChoiceNote>,
}

/// Escapes the characters that separate a note's fields, and the quote and
/// line breaks a message may not contain, as `%XX`.
fn escape_field(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '%' | '|' | ';' | '=' | '"' | '\n' | '\r' | ')' | '(' => {
                let _ = write!(out, "%{:02X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out
}

/// Reverses [`escape_field`]; `None` on a malformed escape.
fn unescape_field(text: &str) -> Option<String> {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars();
    while let Some(c) = chars.next() {
        if c == '%' {
            let hex: String = chars.by_ref().take(2).collect();
            let code = u32::from_str_radix(&hex, 16).ok()?;
            out.push(char::from_u32(code)?);
        } else {
            out.push(c);
        }
    }
    Some(out)
}

/// A value with at most four decimals (`-inf` for none).
fn value_text(value: f64) -> String {
    if value == f64::NEG_INFINITY {
        "-inf".to_string()
    } else {
        num(value, 4)
    }
}

impl KeeperNote {
    /// The note as the text of a log message:
    /// `learnpnp keeper=1|action=Hold|cycle=12|at=...|chosen=0|option=Hold.start;14.2;31|...`.
    pub fn to_message(&self) -> String {
        let mut text = format!(
            "{NOTE_PREFIX}keeper={}|action={}",
            self.keeper,
            escape_field(&self.action)
        );
        if let Some(c) = &self.choice {
            let _ = write!(
                text,
                "|cycle={}|at={}|chosen={}",
                c.cycle,
                escape_field(&c.at),
                c.chosen
            );
            for o in &c.options {
                let _ = write!(
                    text,
                    "|option={};{};{}",
                    escape_field(&o.name),
                    value_text(o.value),
                    o.visits
                );
            }
        }
        text
    }

    /// Reads a message written by [`KeeperNote::to_message`]; `Ok(None)` for
    /// any other message, `Err` with the offending field for a malformed note.
    pub fn from_message(text: &str) -> Result<Option<KeeperNote>, String> {
        let Some(body) = text.strip_prefix(NOTE_PREFIX) else {
            return Ok(None);
        };
        let mut keeper = None;
        let mut action = String::new();
        let mut cycle = None;
        let mut at = String::new();
        let mut chosen = None;
        let mut options = Vec::new();
        for field in body.split('|') {
            let (key, value) = field.split_once('=').ok_or_else(|| field.to_string())?;
            let text = || unescape_field(value).ok_or_else(|| field.to_string());
            match key {
                "keeper" => keeper = Some(value.parse::<u8>().map_err(|_| field.to_string())?),
                "action" => action = text()?,
                "cycle" => cycle = Some(value.parse::<u32>().map_err(|_| field.to_string())?),
                "at" => at = text()?,
                "chosen" => chosen = Some(value.parse::<usize>().map_err(|_| field.to_string())?),
                "option" => {
                    let mut parts = value.split(';');
                    let (Some(name), Some(v), Some(n), None) = (parts.next(), parts.next(), parts.next(), parts.next())
                    else {
                        return Err(field.to_string());
                    };
                    options.push(OptionNote {
                        name: unescape_field(name).ok_or_else(|| field.to_string())?,
                        value: v.parse::<f64>().map_err(|_| field.to_string())?,
                        visits: n.parse::<u64>().map_err(|_| field.to_string())?,
                    });
                }
                _ => {}
            }
        }
        let keeper = keeper.ok_or_else(|| "keeper".to_string())?;
        let choice = match (cycle, chosen) {
            (Some(cycle), Some(chosen)) if chosen < options.len() => Some(ChoiceNote {
                cycle,
                at,
                options,
                chosen,
            }),
            (None, None) if options.is_empty() => None,
            _ => return Err("chosen".to_string()),
        };
        Ok(Some(KeeperNote { keeper, action, choice }))
    }
}

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

/// Writes one Keepaway episode as a `ULG5` game log.
#[derive(Debug, Clone)]
pub struct GameLogWriter {
    text: String,
    cycle_seconds: f64,
    kickable: f64,
    /// Per player: kicks, dashes, turns so far (the show's counts).
    counts: [[u32; 3]; NUM_PLAYERS],
    /// Per player: the state bits of the last command (kick or kick fault).
    state: [u32; NUM_PLAYERS],
    /// The notes last written, so that only changes are written again.
    notes: [Option<KeeperNote>; NUM_KEEPERS],
}

impl GameLogWriter {
    /// A log of an episode under `cfg`: the header, the parameters, play on
    /// and the team names.
    pub fn new(cfg: &KeepawayConfig) -> Self {
        let s = &cfg.server;
        let mut text = String::with_capacity(64 * 1024);
        text.push_str(HEADER);
        text.push('\n');
        let params: [(&str, String); 23] = [
            ("ball_size", num(s.ball_size, 6)),
            ("ball_decay", num(s.ball_decay, 6)),
            ("ball_rand", num(s.ball_rand, 6)),
            ("ball_speed_max", num(s.ball_speed_max, 6)),
            ("ball_accel_max", num(s.ball_accel_max, 6)),
            ("player_size", num(s.player_size, 6)),
            ("player_decay", num(s.player_decay, 6)),
            ("player_rand", num(s.player_rand, 6)),
            ("player_speed_max", num(s.player_speed_max, 6)),
            ("player_accel_max", num(s.player_accel_max, 6)),
            ("inertia_moment", num(s.inertia_moment, 6)),
            ("dash_power_rate", num(s.dash_power_rate, 6)),
            ("kick_power_rate", num(s.kick_power_rate, 6)),
            ("kickable_margin", num(s.kickable_margin, 6)),
            ("maxpower", num(s.max_power, 6)),
            ("minpower", num(s.min_power, 6)),
            ("maxmoment", num(s.max_moment, 6)),
            ("minmoment", num(s.min_moment, 6)),
            ("stamina_max", num(STAMINA_MAX, 0)),
            (
                "simulator_step",
                format!("{}", (s.cycle_seconds * 1000.0).round() as i64),
            ),
            ("keepaway", "1".to_string()),
            ("keepaway_length", num(cfg.region.length, 6)),
            ("keepaway_width", num(cfg.region.width, 6)),
        ];
        text.push_str("(server_param ");
        for (name, value) in &params {
            let _ = write!(text, "({name} {value})");
        }
        text.push_str(")\n");
        let _ = writeln!(
            text,
            "(player_type (id 0)(player_speed_max {})(player_decay {})(inertia_moment {})(dash_power_rate {})\
             (player_size {})(kickable_margin {})(kick_rand 0)(extra_stamina 0)(effort_max {})(effort_min {})(kick_power_rate {}))",
            num(s.player_speed_max, 6),
            num(s.player_decay, 6),
            num(s.inertia_moment, 6),
            num(s.dash_power_rate, 6),
            num(s.player_size, 6),
            num(s.kickable_margin, 6),
            num(s.effort, 6),
            num(s.effort, 6),
            num(s.kick_power_rate, 6),
        );
        let _ = writeln!(text, "(playmode 0 play_on)");
        let _ = writeln!(text, "(team 0 {KEEPER_TEAM} {TAKER_TEAM} 0 0)");
        GameLogWriter {
            text,
            cycle_seconds: s.cycle_seconds,
            kickable: s.kickable_distance(),
            counts: [[0; 3]; NUM_PLAYERS],
            state: [0; NUM_PLAYERS],
            notes: Default::default(),
        }
    }

    /// The state of `world` as the show of cycle `world.cycle`, preceded by the
    /// keepers' notes that changed since the last show (`notes[k]` for keeper k).
    pub fn show(&mut self, world: &FieldState, notes: &[Option<KeeperNote>]) {
        for (k, note) in notes.iter().enumerate().take(NUM_KEEPERS) {
            if note.is_some() && *note != self.notes[k] {
                if let Some(n) = note {
                    let _ = writeln!(self.text, "(msg {} {LOG_BOARD} \"{}\")", world.cycle, n.to_message());
                }
                self.notes[k].clone_from(note);
            }
        }
        let t = &mut self.text;
        let _ = write!(
            t,
            "(show {} ((b) {} {} {} {})",
            world.cycle,
            num(world.ball.pos.x, 4),
            num(world.ball.pos.y, 4),
            num(world.ball.vel.x, 4),
            num(world.ball.vel.y, 4)
        );
        for (side, sign, first, count) in [('l', 1.0, 0, NUM_KEEPERS), ('r', -1.0, NUM_KEEPERS, NUM_TAKERS)] {
            for unum in 1..=MAX_PLAYER {
                let _ = write!(t, " (({side} {unum}) 0 ");
                if unum <= count {
                    let i = first + unum - 1;
                    let p = &world.players[i];
                    let [kicks, dashes, turns] = self.counts[i];
                    let _ = write!(
                        t,
                        "{:#x} {} {} {} {} {} 0 (v h {}) (s {} 1 1 {}) (c {kicks} {dashes} {turns} 0 0 0 0 0 0 0 0))",
                        STATE_STAND | self.state[i],
                        num(p.pos.x, 4),
                        num(p.pos.y, 4),
                        num(p.vel.x, 4),
                        num(p.vel.y, 4),
                        num(p.body, 3),
                        num(VISIBLE_ANGLE, 0),
                        num(STAMINA_MAX, 0),
                        num(STAMINA_CAPACITY, 0),
                    );
                } else {
                    // Not in the game: the server's bench position, state 0.
                    let x = -(unum as f64) * 3.0 * sign;
                    let _ = write!(
                        t,
                        "0 {} {} 0 0 0 0 (v h {}) (s {} 1 1 {}) (c 0 0 0 0 0 0 0 0 0 0 0))",
                        num(x, 4),
                        num(-PITCH_HALF_WIDTH - 3.0, 4),
                        num(VISIBLE_ANGLE, 0),
                        num(STAMINA_MAX, 0),
                        num(STAMINA_CAPACITY, 0),
                    );
                }
            }
        }
        t.push_str(")\n");
    }

    /// The commands the players sent in the cycle of `world` (before it is
    /// stepped): counted, and a kick marks the player kicking (or missing the
    /// ball) in the next show.
    pub fn commands(&mut self, world: &FieldState, commands: &[Command; NUM_PLAYERS]) {
        for (i, cmd) in commands.iter().enumerate() {
            self.state[i] = 0;
            if !cmd.is_finite() {
                continue;
            }
            match cmd {
                Command::None => {}
                Command::Kick { .. } => {
                    self.counts[i][0] += 1;
                    let reach = world.players[i].pos.dist_sq(world.ball.pos) <= self.kickable * self.kickable;
                    self.state[i] = if reach { STATE_KICK } else { STATE_KICK_FAULT };
                }
                Command::Dash { .. } => self.counts[i][1] += 1,
                Command::Turn { .. } => self.counts[i][2] += 1,
            }
        }
    }

    /// The finished log: the referee's message at the end (as rcssserver's
    /// keepaway referee says it) and a last line saying why the episode ended.
    pub fn finish(mut self, cycle: u32, end: Option<EndReason>) -> String {
        let _ = writeln!(self.text, "(msg {cycle} {MSG_BOARD} \"(referee training Keepaway 1)\")");
        let why = match end {
            Some(EndReason::Out) => "the ball left the region",
            Some(EndReason::Taken) => "a taker held the ball",
            Some(EndReason::CycleLimit) => "the cycle limit was reached",
            None => "the episode was cut",
        };
        let _ = writeln!(
            self.text,
            "(msg {cycle} {MSG_BOARD} \"episode over after {cycle} cycles ({} s): {why}\")",
            num(f64::from(cycle) * self.cycle_seconds, 1)
        );
        self.text
    }
}

/// A player in one show of a game log.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlayerFrame {
    /// `l` (keepers) or `r` (takers).
    pub side: char,
    /// The uniform number.
    pub unum: u8,
    /// Position (m).
    pub x: f64,
    /// Position (m).
    pub y: f64,
    /// Body direction (degrees).
    pub body: f64,
    /// Whether the player kicked in the last cycle.
    pub kicking: bool,
}

/// One show: the ball and the players in the game at one cycle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Frame {
    /// The cycle.
    pub time: u32,
    /// The ball's position (m).
    pub ball: [f64; 2],
    /// The enabled players (state not 0), in log order.
    pub players: Vec<PlayerFrame>,
}

/// A keeper note and the cycle of its message.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimedNote {
    /// The cycle.
    pub time: u32,
    /// The note.
    pub note: KeeperNote,
}

/// A message of the log that is no keeper note (the referee's, for example).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimedMessage {
    /// The cycle.
    pub time: u32,
    /// Its text.
    pub text: String,
}

/// What a game log holds, as far as a replay needs it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GameLog {
    /// The log version of the header (4 to 6).
    pub version: u32,
    /// The keepaway region (length, width) when the server ran in keepaway mode.
    pub keepaway: Option<[f64; 2]>,
    /// Seconds per cycle (`simulator_step`, 0.1 by default).
    pub cycle_seconds: f64,
    /// Ball radius (m).
    pub ball_size: f64,
    /// Player radius (m).
    pub player_size: f64,
    /// The left and right team names (empty when the log names none).
    pub teams: [String; 2],
    /// Every show, in log order.
    pub frames: Vec<Frame>,
    /// Every keeper note, in log order.
    pub notes: Vec<TimedNote>,
    /// Every other message, in log order.
    pub messages: Vec<TimedMessage>,
}

/// What is wrong with a game log: the line, the offending token and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {reason}: '{token}'")]
pub struct RcgError {
    /// The line (1-based; the header is line 1).
    pub line: usize,
    /// The offending token (cut to 60 characters).
    pub token: String,
    /// What was expected.
    pub reason: String,
}

/// A game log file that cannot be read; the message starts with its path.
#[derive(Debug, thiserror::Error)]
pub enum GameLogFileError {
    /// Reading failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The text is no game log this reader understands.
    #[error("{path}, {source}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        source: RcgError,
    },
}

/// An s-expression of a log line.
#[derive(Debug, Clone, PartialEq)]
enum Sexp<'a> {
    /// A bare token.
    Atom(&'a str),
    /// A double-quoted string (without its quotes).
    Text(&'a str),
    /// A parenthesised list.
    List(Vec<Sexp<'a>>),
}

impl<'a> Sexp<'a> {
    fn atom(&self) -> Option<&'a str> {
        match self {
            Sexp::Atom(a) => Some(a),
            _ => None,
        }
    }

    fn list(&self) -> Option<&[Sexp<'a>]> {
        match self {
            Sexp::List(items) => Some(items),
            _ => None,
        }
    }

    /// The text of an element, for error messages.
    fn show(&self) -> String {
        match self {
            Sexp::Atom(a) => (*a).to_string(),
            Sexp::Text(t) => format!("\"{t}\""),
            Sexp::List(items) => format!("({})", items.iter().map(Sexp::show).collect::<Vec<_>>().join(" ")),
        }
    }
}

/// The text cut to 60 characters.
fn cut(text: &str) -> String {
    match text.char_indices().nth(60) {
        Some((i, _)) => format!("{}…", &text[..i]),
        None => text.to_string(),
    }
}

/// Parses one line into an s-expression.
fn parse_sexp(line: &str) -> Result<Sexp<'_>, (String, &'static str)> {
    let bytes = line.as_bytes();
    let mut stack: Vec<Vec<Sexp<'_>>> = Vec::new();
    let mut i = 0;
    let mut done: Option<Sexp<'_>> = None;
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b' ' | b'\t' | b'\r' => i += 1,
            _ if done.is_some() => return Err((cut(&line[i..]), "text after the closing parenthesis")),
            b'(' => {
                stack.push(Vec::new());
                i += 1;
            }
            b')' => {
                let items = stack.pop().ok_or_else(|| (cut(&line[i..]), "unbalanced ')'"))?;
                let list = Sexp::List(items);
                match stack.last_mut() {
                    Some(parent) => parent.push(list),
                    None => done = Some(list),
                }
                i += 1;
            }
            b'"' => {
                // A message runs to the last quote followed by ')' (rcssmonitor's rule).
                let rest = &line[i + 1..];
                let end = rest
                    .rfind("\")")
                    .ok_or_else(|| (cut(&line[i..]), "unterminated string"))?;
                let parent = stack
                    .last_mut()
                    .ok_or_else(|| (cut(&line[i..]), "a string outside parentheses"))?;
                parent.push(Sexp::Text(&rest[..end]));
                i += end + 2;
            }
            _ => {
                let start = i;
                while i < bytes.len() && !matches!(bytes[i], b' ' | b'\t' | b'\r' | b'(' | b')' | b'"') {
                    i += 1;
                }
                let parent = stack
                    .last_mut()
                    .ok_or_else(|| (cut(&line[start..]), "a token outside parentheses"))?;
                parent.push(Sexp::Atom(&line[start..i]));
            }
        }
    }
    match (done, stack.is_empty()) {
        (Some(sexp), true) => Ok(sexp),
        _ => Err((cut(line), "unbalanced '('")),
    }
}

/// Line-level parsing state.
struct LineParser {
    line: usize,
}

impl LineParser {
    fn error(&self, token: &str, reason: impl Into<String>) -> RcgError {
        RcgError {
            line: self.line,
            token: cut(token),
            reason: reason.into(),
        }
    }

    fn number<T: std::str::FromStr>(&self, item: Option<&Sexp<'_>>, what: &str) -> Result<T, RcgError> {
        let text = item.and_then(Sexp::atom).ok_or_else(|| {
            self.error(
                &item.map_or_else(|| "end of list".to_string(), Sexp::show),
                format!("expected {what}"),
            )
        })?;
        text.parse::<T>()
            .map_err(|_| self.error(text, format!("expected {what}")))
    }

    fn real(&self, item: Option<&Sexp<'_>>, what: &str) -> Result<f64, RcgError> {
        let v: f64 = self.number(item, what)?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(&item.map(Sexp::show).unwrap_or_default(), format!("expected {what}")))
        }
    }

    /// `(show T [(pm n)] [(tm ...)] ((b) x y vx vy) player...)`.
    fn show(&self, items: &[Sexp<'_>]) -> Result<Frame, RcgError> {
        let time: u32 = self.number(items.get(1), "the cycle")?;
        let mut ball = None;
        let mut players = Vec::new();
        for item in &items[2..] {
            let list = item
                .list()
                .ok_or_else(|| self.error(&item.show(), "expected a ball or player list"))?;
            let head = list.first();
            if let Some("pm" | "tm") = head.and_then(Sexp::atom) {
                continue;
            }
            let id = head
                .and_then(Sexp::list)
                .ok_or_else(|| self.error(&item.show(), "expected (b) or (side unum)"))?;
            match id {
                [Sexp::Atom("b")] => {
                    ball = Some([
                        self.real(list.get(1), "the ball's x")?,
                        self.real(list.get(2), "the ball's y")?,
                    ]);
                }
                [Sexp::Atom(side @ ("l" | "r")), unum] => {
                    let unum: u8 = self.number(Some(unum), "a uniform number")?;
                    if unum == 0 || usize::from(unum) > MAX_PLAYER {
                        return Err(self.error(&unum.to_string(), "a uniform number is 1 to 11"));
                    }
                    let state_text = list
                        .get(2)
                        .and_then(Sexp::atom)
                        .ok_or_else(|| self.error(&item.show(), "expected the player's state"))?;
                    let state = u32::from_str_radix(state_text.trim_start_matches("0x"), 16)
                        .map_err(|_| self.error(state_text, "expected the player's state (hexadecimal)"))?;
                    if state == 0 {
                        continue;
                    }
                    players.push(PlayerFrame {
                        side: side.chars().next().unwrap_or('l'),
                        unum,
                        x: self.real(list.get(3), "the player's x")?,
                        y: self.real(list.get(4), "the player's y")?,
                        body: self.real(list.get(7), "the player's body direction")?,
                        kicking: state & STATE_KICK != 0,
                    });
                }
                _ => return Err(self.error(&item.show(), "expected (b) or (side unum)")),
            }
        }
        let ball = ball.ok_or_else(|| self.error(&format!("show {time}"), "a show without the ball"))?;
        Ok(Frame { time, ball, players })
    }
}

impl GameLog {
    /// Reads a text game log of version 4, 5 or 6 (`ULG4`..`ULG6`).
    ///
    /// Lines the replay does not need (`player_param`, `player_type`,
    /// `playmode`, `team_graphic`, `draw`...) are skipped after their
    /// parentheses are checked; a malformed show, message or header is an
    /// error naming the line and the token.
    pub fn parse(text: &str) -> Result<GameLog, RcgError> {
        let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
        let (_, header) = lines.next().ok_or_else(|| RcgError {
            line: 1,
            token: String::new(),
            reason: "empty file (expected the header ULG5)".to_string(),
        })?;
        let header = header.trim();
        let version = header
            .strip_prefix("ULG")
            .and_then(|v| v.parse::<u32>().ok())
            .ok_or_else(|| RcgError {
                line: 1,
                token: cut(header),
                reason: "not a text game log (expected the header ULG4, ULG5 or ULG6)".to_string(),
            })?;
        if !(4..=6).contains(&version) {
            return Err(RcgError {
                line: 1,
                token: header.to_string(),
                reason: "unsupported log version (text logs ULG4 to ULG6 are read)".to_string(),
            });
        }
        let mut log = GameLog {
            version,
            keepaway: None,
            cycle_seconds: 0.1,
            ball_size: 0.085,
            player_size: 0.3,
            teams: [String::new(), String::new()],
            frames: Vec::new(),
            notes: Vec::new(),
            messages: Vec::new(),
        };
        let mut keepaway = [false, false];
        let mut region = [20.0, 20.0];
        for (number, line) in lines {
            if line.trim().is_empty() {
                continue;
            }
            let p = LineParser { line: number };
            let sexp = parse_sexp(line).map_err(|(token, reason)| p.error(&token, reason))?;
            let items = sexp.list().unwrap_or(&[]);
            let name = items
                .first()
                .and_then(Sexp::atom)
                .ok_or_else(|| p.error(line, "expected a line such as (show ...)"))?;
            match name {
                "show" => {
                    let frame = p.show(items)?;
                    log.frames.push(frame);
                }
                "msg" => {
                    let time: u32 = p.number(items.get(1), "the cycle")?;
                    let text = match items.get(3) {
                        Some(Sexp::Text(t)) => *t,
                        other => {
                            return Err(p.error(
                                &other.map_or_else(|| "end of list".to_string(), Sexp::show),
                                "expected the message in quotes",
                            ));
                        }
                    };
                    match KeeperNote::from_message(text) {
                        Ok(Some(note)) => log.notes.push(TimedNote { time, note }),
                        Ok(None) => log.messages.push(TimedMessage {
                            time,
                            text: text.to_string(),
                        }),
                        Err(field) => return Err(p.error(&field, "malformed keeper note")),
                    }
                }
                "team" => {
                    for (slot, item) in log.teams.iter_mut().zip(items.iter().skip(2)) {
                        let name = item.atom().unwrap_or("");
                        *slot = if name == "null" {
                            String::new()
                        } else {
                            name.to_string()
                        };
                    }
                }
                "server_param" => {
                    for item in &items[1..] {
                        let Some([Sexp::Atom(key), value]) = item.list() else {
                            continue;
                        };
                        let value = value.atom().unwrap_or("");
                        let real = || value.parse::<f64>().ok().filter(|v| v.is_finite() && *v > 0.0);
                        match *key {
                            "keepaway" => keepaway[0] = matches!(value, "1" | "true" | "on"),
                            "keepaway_length" => region[0] = real().unwrap_or(region[0]),
                            "keepaway_width" => region[1] = real().unwrap_or(region[1]),
                            "ball_size" => log.ball_size = real().unwrap_or(log.ball_size),
                            "player_size" => log.player_size = real().unwrap_or(log.player_size),
                            "simulator_step" => log.cycle_seconds = real().map_or(log.cycle_seconds, |ms| ms / 1000.0),
                            _ => {}
                        }
                    }
                    keepaway[1] = true;
                }
                _ => {}
            }
        }
        if keepaway == [true, true] {
            log.keepaway = Some(region);
        }
        if log.frames.is_empty() {
            return Err(RcgError {
                line: text.lines().count(),
                token: String::new(),
                reason: "the log has no show line".to_string(),
            });
        }
        Ok(log)
    }

    /// Reads the game log at `path`.
    pub fn read_file(path: &Path) -> Result<GameLog, GameLogFileError> {
        let text = std::fs::read_to_string(path).map_err(|source| GameLogFileError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        GameLog::parse(&text).map_err(|source| GameLogFileError::Format {
            path: path.to_path_buf(),
            source,
        })
    }
}

#[cfg(test)]
mod tests {
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
