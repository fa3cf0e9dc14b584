//! Writing one Keepaway episode as a `ULG5` game log.

use std::fmt::Write as _;

use super::*;
use crate::command::Command;
use crate::params::KeepawayConfig;
use crate::referee::EndReason;
use crate::world::{FieldState, NUM_KEEPERS, NUM_PLAYERS, NUM_TAKERS};

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
