//! Reading text game logs (versions 4 to 6) back: shows, play modes, messages
//! and the keepers' notes.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::*;

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
    pub(crate) kicking: bool,
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
    pub(crate) cycle_seconds: f64,
    /// Ball radius (m).
    pub(crate) ball_size: f64,
    /// Player radius (m).
    pub(crate) player_size: f64,
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
    pub(crate) reason: String,
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
pub(super) enum Sexp<'a> {
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
pub(super) fn parse_sexp(line: &str) -> Result<Sexp<'_>, (String, &'static str)> {
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
