//! When the players' see messages arrive, and when the players act: the
//! soccer server's timer and visual sender, and the keepaway framework's
//! synchronisation of its sees. This is the timing side of
//! [`super::params::VisionMode::Framework`](crate::params::VisionMode::Framework); [`super::see`](crate::see) says what a see
//! carries.
//!
//! Versions. The keepaway framework 0.6 speaks protocol 9.3 (`main.cc`:
//! `dVersion`) and its README recommends rcssserver 9.4.5. rcssserver's git
//! history starts at 11.1, so the server's rules are read there; the NEWS and
//! ChangeLog entries from 9.4.5 to 11.1 record no change to the timers'
//! schedule, the visual sender's counter or `change_view` (only ports and
//! clean-ups of those files), and from 11.1 to 19 the functions below do the
//! same in everything used here (12 adds the `(synch_see)` command and its
//! visuals, which the framework never sends).
//!
//! The server (rcssserver 11.1):
//! - `StandardTimer::run` (`stdtimer.cc`), the real-time timer: on a 10 ms
//!   clock (`TIMEDELTA`) in 300 ms periods (`lcm_step`), each tick first
//!   receives the clients' messages (`recv_step`, 10 ms), then every 100 ms
//!   runs a step and sends the body senses, then calls the visual sender when
//!   `send_step / 4` (37.5 ms) more is due: at 0, 40, 80, 120, 150, 190, 230
//!   and 270 ms of the period (`visual_call_time`);
//! - `SyncTimer::run` (`synctimer.cc`), synchronous mode: the same schedule in
//!   simulated time, then, `synch_offset` into each step, `Stadium::doSendThink`
//!   (`field.C`), which sends `(think)`, receives the clients' messages (the
//!   only place this timer does) and waits for their `(done)`;
//! - `VisualSenderPlayerV1::sendVisual` (`visual.cc`): each visual call adds one
//!   to the player's counter (0 when it connects) and sends it a see when the
//!   counter reaches the player's interval, which resets it (`VisualSender`);
//! - `Player::change_view` (`player.cc`): the interval is 4 at normal width and
//!   high quality (a new player's view), 2 at narrow width, and half that at
//!   low quality; the counter is left as it is;
//! - `KeepawayRef::analyse` (`referee.cc`): the play mode stays before kick-off
//!   until `keepaway_start` seconds have passed on the wall clock since the
//!   server started (8 s in `keepaway.sh`); episodes then follow one another
//!   in play-on (`resetField` changes no play mode); the server's time stands
//!   still before the kick-off (`Stadium::step`, `field.C`).
//!
//! The player (keepaway framework 0.6, `player/SenseHandler.cc`):
//! - `SenseHandler::synchronize`, called on every message before it is parsed
//!   (`analyzeMessage`), does nothing in synchronous mode. In real time, once
//!   the player's clock is past its third cycle before the kick-off it sends
//!   `(change_view narrow low)`, so that every visual call sends it a see
//!   (three, three and two in the period's three steps); from the second
//!   cycle after, at the first message of each cycle, it looks at how many
//!   sees the previous cycle brought, and when they were two (the period's
//!   last step) it sends `(change_view normal high)`. The server applies it at
//!   its next tick, after the period's first see, so the player's sees fall on
//!   the period's calls 0 and 4: at 0 and 50 ms into its first two steps. One
//!   connection time in 30 misleads it: a player connected in the 10 ms
//!   before a period's last step, whose first sees then miss every last step,
//!   starts at the body sense of a first step, whose first see comes before
//!   the narrow view is in force; it takes that step's two sees for the
//!   period's last and ends on calls 3 and 7 (20 and 70 ms into the last two
//!   steps, both in time to act). It does all this once per run (`bNeedSync`
//!   is a static); in play-on it only asks for normal and high again while
//!   its body sense still reports low quality (`Synchroniser`);
//! - `analyzeSeeMessage` counts the sees of the current cycle
//!   (`m_iSeeCounter`), taking only those stamped with the cycle of the last
//!   body sense; the player's clock (`Time`) is that cycle and how many cycles
//!   it stood still (`Time::updateTime`);
//! - in real time the player acts at once on a see of the current cycle, and
//!   otherwise at 70% of the step in the cycle after one without a see and at
//!   85% in the next (`setTimeSignal`, `PlayerSettings`); in synchronous mode
//!   it acts on the think (`KeepawayPlayer::mainLoop`,
//!   `WorldModel::processRecvThink`).
//!
//! `keepaway.sh` starts the server, then the keepers 2 s later and the takers
//! 2 s after them; nothing fixes where in the server's 300 ms period each
//! player connects, so that is drawn (`phases_at_kick_off`).
//!
//! Left out: messages arrive and are handled within a tick (10 ms); the
//! players' hear messages (one between a cycle's body sense and its first see
//! would only do that cycle's check of `synchronize` earlier in the same
//! tick); the server never runs late (the timer's catch-up rule never fires).

use super::params::ServerTimer;
use super::world::{NUM_KEEPERS, NUM_PLAYERS};

/// The server's simulation step, ms (`simulator_step`).
const SIM_STEP_MS: u32 = 100;
/// The server timer's clock, ms (`TIMEDELTA`): events fall on its ticks.
const TICK_MS: u32 = 10;
/// The server's `send_step`, ms: one see per `send_step` at normal width and
/// high quality.
const SEND_STEP_MS: u32 = 150;
/// Visual calls per `send_step` (`StandardTimer::run`: every `send_step * 0.25`).
const VISUAL_CALLS_PER_SEND_STEP: u32 = 4;
/// The server timer's period, ms (`lcm_step`, the least common multiple of its steps).
pub(crate) const WINDOW_MS: u32 = 300;
/// Cycles in the timer's period.
pub(crate) const WINDOW_CYCLES: u32 = WINDOW_MS / SIM_STEP_MS;
/// Visual calls in the timer's period.
const CALLS_PER_WINDOW: u32 = WINDOW_MS * VISUAL_CALLS_PER_SEND_STEP / SEND_STEP_MS;
/// Calls between two sees at normal width and high quality (`Player::change_view`).
const CALLS_PER_SEE: u32 = 4;
/// The framework's wait before acting in the cycle after the one without a see,
/// as a fraction of the step (`PlayerSettings`: `dFractionWaitSeeBegin`).
const WAIT_SEE_BEGIN: f64 = 0.70;
/// The framework's wait in the next cycle (`dFractionWaitSeeEnd`).
const WAIT_SEE_END: f64 = 0.85;
/// When the synchronous server sends its think, ms into the step (`keepaway.sh`:
/// `synch_offset=80`).
const SYNCH_OFFSET_MS: u32 = 80;
/// When `keepaway.sh` launches the keepers, ms after the server (`sleep 2`).
const KEEPERS_LAUNCHED_MS: u32 = 2000;
/// When it launches the takers (another `sleep 2`).
const TAKERS_LAUNCHED_MS: u32 = 4000;
/// The earliest kick-off, ms after the server started: `KeepawayRef::analyse`
/// starts play-on once more than `keepaway_start` whole seconds (8 in
/// `keepaway.sh`) separate the wall clock from the server's start, so between
/// 8 and 9 s; the earliest leaves the players the least time to synchronise.
const KICK_OFF_MS: u32 = 8000;

/// Which of the server's four visual calls of every `send_step` carry a
/// player's see: fixed before the first kick-off, so fixed for a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SeePhase(u8);

impl SeePhase {
    /// The four phases: phase `p` sees at the period's visual calls `p` and `p + 4`.
    pub const ALL: [SeePhase; 4] = [SeePhase(0), SeePhase(1), SeePhase(2), SeePhase(3)];

    /// Phase `i` (`0..4`), if in range.
    pub fn new(i: u8) -> Option<SeePhase> {
        SeePhase::ALL.get(usize::from(i)).copied()
    }

    /// The phase whose sees include the period's call `k`.
    fn of_call(k: u32) -> SeePhase {
        // Below 4, so the cast is exact.
        SeePhase((k % CALLS_PER_SEE) as u8)
    }

    /// Offsets (ms from the start of the timer's period) of this phase's sees.
    fn see_times(self) -> impl Iterator<Item = u32> {
        (0..CALLS_PER_WINDOW)
            .filter(move |k| k % CALLS_PER_SEE == u32::from(self.0))
            .map(visual_call_time)
    }
}

/// When the server's `k`-th visual call of its period happens, ms: the first
/// tick of its 10 ms clock at or after `k x send_step / 4`.
fn visual_call_time(k: u32) -> u32 {
    let due_ticks = (k * SEND_STEP_MS).div_ceil(VISUAL_CALLS_PER_SEND_STEP * TICK_MS);
    due_ticks * TICK_MS
}

/// The visual call of the period at `ms` into it, if one falls there.
fn visual_call_at(ms: u32) -> Option<u32> {
    (0..CALLS_PER_WINDOW).find(|&k| visual_call_time(k) == ms)
}

/// Whether a see message arrives in a cycle, and whether before the player acts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeeArrival {
    /// No see in this cycle: the player acts on its world model's prediction.
    None,
    /// A see of this cycle's state arrives before the player sends its command.
    BeforeDecision,
    /// A see arrives after the command is sent (it informs the next cycle).
    AfterDecision,
}

impl SeeArrival {
    /// Whether a see message arrives in the cycle at all.
    pub(crate) fn sees(self) -> bool {
        self != SeeArrival::None
    }
}

/// The see of a player with `phase` in the cycle at position `cycle` (taken
/// modulo 3) of the server's 300 ms period, with `timer`.
///
/// Two of every three cycles carry a see. In real time the framework's player
/// (`SenseHandler::setTimeSignal`, re-synchronised in `analyzeSeeMessage`)
/// expects the pattern: in the cycle after the one without a see it sends its
/// command at 70% of the step, in the next at 85%; a see that arrives later
/// than that is processed after the command. Relative to the step, the phases
/// see at 0 and 50 ms (both in time), 40 and 90 ms (the second too late), 80
/// ms and, a cycle later, 30 ms, or 20 and 70 ms. In synchronous mode the
/// player acts on the think, 80 ms into the step, after the visuals of that
/// tick (`SyncTimer::run` sends them first): only the 90 ms see is late.
pub fn see_arrival(phase: SeePhase, cycle: u32, timer: ServerTimer) -> SeeArrival {
    let w = cycle % WINDOW_CYCLES;
    let mut offset = None;
    let mut seen = [false; WINDOW_CYCLES as usize];
    for t in phase.see_times() {
        let c = t / SIM_STEP_MS;
        if let Some(s) = seen.get_mut(c as usize) {
            *s = true;
        }
        if c == w {
            offset = Some(t % SIM_STEP_MS);
        }
    }
    let Some(offset) = offset else {
        return SeeArrival::None;
    };
    let in_time = match timer {
        ServerTimer::RealTime => {
            // The cycle without a see; the framework waits `WAIT_SEE_BEGIN` in the next one.
            let blind = (0..WINDOW_CYCLES).find(|&c| !seen[c as usize]).unwrap_or(0);
            let wait = if (blind + 1) % WINDOW_CYCLES == w {
                WAIT_SEE_BEGIN
            } else {
                WAIT_SEE_END
            };
            f64::from(offset) < wait * f64::from(SIM_STEP_MS)
        }
        ServerTimer::Synchronous => offset <= SYNCH_OFFSET_MS,
    };
    if in_time {
        SeeArrival::BeforeDecision
    } else {
        SeeArrival::AfterDecision
    }
}

/// The two views the framework asks for (`change_view`), as far as when its
/// sees come is concerned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum View {
    /// Narrow width and low quality: a see at every visual call.
    NarrowLow,
    /// Normal width and high quality (a new player's view): a see every fourth call.
    NormalHigh,
}

impl View {
    /// Visual calls per see (`Player::change_view`: narrow 2, normal 4, halved
    /// for low quality).
    fn interval(self) -> u32 {
        match self {
            View::NarrowLow => 1,
            View::NormalHigh => CALLS_PER_SEE,
        }
    }
}

/// The server's visual sender of one player (`VisualSenderPlayerV1::sendVisual`
/// with the player's view interval).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct VisualSender {
    /// Calls since the last see (`m_sendcnt`; 0 when the player connects).
    count: u32,
    /// The player's view (`M_vis_send` follows from it).
    view: View,
}

impl VisualSender {
    /// The sender of a player that has just connected.
    fn new() -> Self {
        VisualSender {
            count: 0,
            view: View::NormalHigh,
        }
    }

    /// One visual call: whether it sends the player a see.
    fn call(&mut self) -> bool {
        self.count += 1;
        if self.count >= self.view.interval() {
            self.count = 0;
            true
        } else {
            false
        }
    }

    /// `Player::change_view`: a new interval, the counter kept.
    fn change_view(&mut self, view: View) {
        self.view = view;
    }

    /// The phase of the next see, if the next call is the period's `next_call`.
    fn next_phase(&self, next_call: u32) -> SeePhase {
        let calls = self.view.interval().saturating_sub(self.count).max(1);
        SeePhase::of_call(next_call + calls - 1)
    }
}

/// The framework player's clock (`Time`): the cycle of its last body sense
/// and how many cycles the time stood still there. Ordered as
/// `Time::getTimeDifference` orders it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Time {
    cycle: i32,
    stopped: i32,
}

impl Time {
    /// Before the first body sense (`Time`'s default, -1).
    const UNKNOWN: Time = Time { cycle: -1, stopped: 0 };
    /// The clock `synchronize` must be past to start (`Time( 0, 2 )`).
    const SYNC_START: Time = Time { cycle: 0, stopped: 2 };

    /// `Time::updateTime`: a repeated cycle counts as time standing still.
    fn update(&mut self, cycle: i32) {
        if self.cycle == cycle {
            self.stopped += 1;
        } else {
            *self = Time { cycle, stopped: 0 };
        }
    }
}

/// A framework player's side of the synchronisation (`SenseHandler`): its
/// clock, its count of sees and `synchronize`'s state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Synchroniser {
    /// The last body sense's time (`getCurrentTime`).
    now: Time,
    /// Whether the last body sense reported low quality (`getAgentViewQuality`).
    low: bool,
    /// The time of the last see counted (`getTimeLastSeeMessage`).
    last_see: Time,
    /// Sees counted in that cycle (`m_iSeeCounter`).
    sees: u32,
    /// Whether it has still to synchronise (`bNeedSync`: once per run).
    needed: bool,
    /// Whether it is synchronising (`m_bBusySync`).
    busy: bool,
    /// The cycle after which it looks at the sees (`timeSync`).
    sync_time: Time,
}

impl Synchroniser {
    /// A player that has just connected.
    fn new() -> Self {
        Synchroniser {
            now: Time::UNKNOWN,
            low: false,
            last_see: Time::UNKNOWN,
            sees: 0,
            needed: true,
            busy: false,
            sync_time: Time::UNKNOWN,
        }
    }

    /// `SenseHandler::synchronize` before a message is parsed (real time
    /// only), with the play mode the player knows: the view it asks for, if any.
    fn synchronize(&mut self, play_on: bool) -> Option<View> {
        let mut asked = None;
        if play_on {
            self.busy = false;
            self.sync_time = Time::UNKNOWN;
            if self.low {
                asked = Some(View::NormalHigh);
            }
        }
        if !self.needed || play_on || self.now <= Time::SYNC_START {
            return asked;
        }
        if !self.busy {
            // Start: a see at every call, counted from the next cycle on.
            self.busy = true;
            self.sync_time = Time {
                cycle: self.now.cycle,
                stopped: self.now.stopped + 1,
            };
            return Some(View::NarrowLow);
        }
        if self.sync_time < self.now {
            if self.sees == 2 {
                // The previous cycle was the period's last: this one starts it.
                self.busy = false;
                self.needed = false;
                return Some(View::NormalHigh);
            }
            self.sync_time = self.now;
        }
        None
    }

    /// A body sense of the server's `cycle` (`analyzeSenseMessage`), reporting
    /// the player's view.
    fn sense(&mut self, cycle: i32, view: View) {
        self.now.update(cycle);
        self.low = view == View::NarrowLow;
    }

    /// A see of the server's `cycle` (`analyzeSeeMessage`): counted if it is
    /// stamped with the body sense's cycle.
    fn see(&mut self, cycle: i32) {
        if self.now.cycle != cycle {
            return;
        }
        if self.last_see == self.now {
            self.sees += 1;
        } else {
            self.sees = 1;
        }
        self.last_see = self.now;
    }
}

/// One player from the server's start to just after the kick-off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Connection {
    /// When its connection reaches the server, ms after the server started.
    arrives_ms: u32,
    /// Whether the server has taken it.
    connected: bool,
    /// The server's visual sender.
    sender: VisualSender,
    /// The view the player asked for, applied at the server's next receive.
    asked: Option<View>,
    /// The player's side.
    player: Synchroniser,
}

impl Connection {
    /// A message reaches the player; in real time it runs `synchronize` first.
    fn message(&mut self, timer: ServerTimer, play_on: bool) {
        if timer == ServerTimer::RealTime
            && let Some(view) = self.player.synchronize(play_on)
        {
            self.asked = Some(view);
        }
    }

    /// The server receives the player's messages: its connection, once it
    /// has arrived, then the view it asked for.
    fn receive(&mut self, ms: u32) {
        if !self.connected && ms >= self.arrives_ms {
            self.connected = true;
        }
        if let Some(view) = self.asked.take() {
            self.sender.change_view(view);
        }
    }
}

/// Every player's connection and synchronisation from the server's start
/// through the kick-off and one period of play-on, with `timer`. Player `i`
/// connects `offsets_ms[i]` (taken modulo 300) into the first server period
/// that starts after `keepaway.sh` launched it. Returns the players and the
/// time (ms) of the first tick not simulated.
fn before_kick_off(offsets_ms: [u32; NUM_PLAYERS], timer: ServerTimer) -> ([Connection; NUM_PLAYERS], u32) {
    let mut players = [0, 1, 2, 3, 4].map(|i: usize| {
        let launched = if i < NUM_KEEPERS {
            KEEPERS_LAUNCHED_MS
        } else {
            TAKERS_LAUNCHED_MS
        };
        Connection {
            arrives_ms: launched.div_ceil(WINDOW_MS) * WINDOW_MS + offsets_ms[i] % WINDOW_MS,
            connected: false,
            sender: VisualSender::new(),
            asked: None,
            player: Synchroniser::new(),
        }
    });
    let end_ms = KICK_OFF_MS + WINDOW_MS;
    let mut play_on = false;
    for ms in (TICK_MS..=end_ms).step_by(TICK_MS as usize) {
        // Real time: every tick starts by receiving (`recv_step`).
        if timer == ServerTimer::RealTime {
            for p in &mut players {
                p.receive(ms);
            }
        }
        // The server's time stands still before the kick-off, and in its step.
        let cycle = i32::try_from(ms.saturating_sub(KICK_OFF_MS) / SIM_STEP_MS).unwrap_or(i32::MAX);
        if ms % SIM_STEP_MS == 0 {
            if ms == KICK_OFF_MS {
                // The referee's `(hear 0 referee play_on)`, parsed after `synchronize`.
                for p in players.iter_mut().filter(|p| p.connected) {
                    p.message(timer, play_on);
                }
                play_on = true;
            }
            for p in players.iter_mut().filter(|p| p.connected) {
                p.message(timer, play_on);
                p.player.sense(cycle, p.sender.view);
            }
        }
        if visual_call_at(ms % WINDOW_MS).is_some() {
            for p in players.iter_mut().filter(|p| p.connected) {
                if p.sender.call() {
                    p.message(timer, play_on);
                    p.player.see(cycle);
                }
            }
        }
        // Synchronous mode receives only during the think.
        if timer == ServerTimer::Synchronous && ms % SIM_STEP_MS == SYNCH_OFFSET_MS {
            for p in &mut players {
                p.receive(ms);
            }
        }
    }
    (players, end_ms + TICK_MS)
}

/// Each player's see phase in the first episode, with `timer`, when player `i`
/// connected `offsets_ms[i]` (modulo 300) into one of the server's 300 ms
/// periods (after `keepaway.sh` launched it, before the kick-off): in
/// real time the phase the framework's synchronisation leaves (the same for
/// every player), in synchronous mode the one its connection gave.
pub(crate) fn phases_at_kick_off(offsets_ms: [u32; NUM_PLAYERS], timer: ServerTimer) -> [SeePhase; NUM_PLAYERS] {
    let (players, next_ms) = before_kick_off(offsets_ms, timer);
    let next_call = (next_ms..next_ms + WINDOW_MS)
        .step_by(TICK_MS as usize)
        .find_map(|ms| visual_call_at(ms % WINDOW_MS))
        .unwrap_or(0);
    players.map(|p| {
        let mut sender = p.sender;
        if let Some(view) = p.asked {
            sender.change_view(view);
        }
        sender.next_phase(next_call)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use SeeArrival::{AfterDecision as A, BeforeDecision as B, None as N};

    #[test]
    fn visual_calls_fall_on_the_timer_ticks() {
        let times: Vec<u32> = (0..CALLS_PER_WINDOW).map(visual_call_time).collect();
        assert_eq!(times, [0, 40, 80, 120, 150, 190, 230, 270]);
    }

    fn table(timer: ServerTimer) -> Vec<[SeeArrival; 3]> {
        SeePhase::ALL
            .iter()
            .map(|&p| [0, 1, 2].map(|c| see_arrival(p, c, timer)))
            .collect()
    }

    #[test]
    fn two_sees_in_three_cycles_and_one_late_phase() {
        assert_eq!(
            table(ServerTimer::RealTime),
            [[B, B, N], [B, A, N], [B, N, B], [N, B, B]]
        );
        for timer in [ServerTimer::RealTime, ServerTimer::Synchronous] {
            for p in SeePhase::ALL {
                for c in 0..9 {
                    assert_eq!(see_arrival(p, c, timer), see_arrival(p, c % 3, timer));
                }
            }
        }
    }

    #[test]
    fn synchronous_players_act_on_the_think_at_80_ms() {
        // The 80 ms see goes out before the think of its tick; the 90 ms one after.
        assert_eq!(
            table(ServerTimer::Synchronous),
            [[B, B, N], [B, A, N], [B, N, B], [N, B, B]]
        );
    }

    #[test]
    fn narrow_low_sees_come_three_three_two() {
        for start in 0..CALLS_PER_SEE {
            let mut sender = VisualSender {
                count: start,
                view: View::NormalHigh,
            };
            sender.change_view(View::NarrowLow);
            let mut per_cycle = [0; WINDOW_CYCLES as usize];
            for k in 0..CALLS_PER_WINDOW {
                if sender.call() {
                    per_cycle[(visual_call_time(k) / SIM_STEP_MS) as usize] += 1;
                }
            }
            assert_eq!(per_cycle, [3, 3, 2], "counter {start} at the change");
        }
    }

    #[test]
    fn a_new_player_sees_every_fourth_call() {
        let mut sender = VisualSender::new();
        let sent: Vec<bool> = (0..8).map(|_| sender.call()).collect();
        assert_eq!(sent, [false, false, false, true, false, false, false, true]);
    }

    /// Every offset of the 300 ms period on the 10 ms clock and between.
    fn offsets() -> impl Iterator<Item = u32> {
        (0..WINDOW_MS).step_by(5)
    }

    /// The phase synchronisation gives a player that connects `offset` ms
    /// into the server's period: the period's calls 0 and 4, except when the
    /// connection comes in the 10 ms before the period's third step. That
    /// player's first body sense is of the third step and its sees miss every
    /// third step, so it starts synchronising at the body sense of a period's
    /// first step, after whose first visual call its narrow view comes into
    /// force: that step shows it two sees and it takes it for the period's
    /// last, which leaves it the calls 3 and 7.
    fn synchronised_phase(offset: u32) -> SeePhase {
        if (191..=200).contains(&offset) {
            SeePhase(3)
        } else {
            SeePhase(0)
        }
    }

    #[test]
    fn synchronised_players_see_at_the_same_early_phase_whenever_they_connect() {
        for a in offsets() {
            for b in offsets().step_by(7) {
                let offsets = [a, b, (a + b) % WINDOW_MS, b, a];
                let (players, _) = before_kick_off(offsets, ServerTimer::RealTime);
                for p in &players {
                    assert!(p.connected && !p.player.needed && !p.player.busy, "offsets {offsets:?}");
                    assert_eq!((p.sender.view, p.asked), (View::NormalHigh, None));
                }
                let phases = phases_at_kick_off(offsets, ServerTimer::RealTime);
                assert_eq!(phases, offsets.map(synchronised_phase), "offsets {offsets:?}");
            }
        }
        // Both phases see twice in three steps, and in time to act: at 0 and 50 ms
        // into the first two steps, or at 20 and 70 ms into the last two.
        let arrivals = table(ServerTimer::RealTime);
        assert_eq!((arrivals[0], arrivals[3]), ([B, B, N], [N, B, B]));
    }

    /// One cycle of messages before the kick-off: its body sense, then
    /// `sees` sees; what `synchronize` asks for at each.
    fn cycle(s: &mut Synchroniser, sees: u32, view: View) -> Vec<Option<View>> {
        let mut asked = vec![s.synchronize(false)];
        s.sense(0, view);
        for _ in 0..sees {
            asked.push(s.synchronize(false));
            s.see(0);
        }
        asked
    }

    #[test]
    fn synchronisation_asks_for_normal_high_after_a_two_see_cycle() {
        let mut s = Synchroniser::new();
        // Clock (0, 0) to (0, 3): the first message after it passed (0, 2) starts.
        let asked: Vec<_> = (0..4).flat_map(|_| cycle(&mut s, 1, View::NormalHigh)).collect();
        assert_eq!(asked.last(), Some(&Some(View::NarrowLow)));
        assert!(asked.iter().rev().skip(1).all(Option::is_none));
        // Narrow and low from (0, 4); its sees are looked at from (0, 5) on, at
        // each cycle's first message after the body sense.
        for sees in [3, 3, 2] {
            assert!(cycle(&mut s, sees, View::NarrowLow).iter().all(Option::is_none));
        }
        assert_eq!(
            cycle(&mut s, 3, View::NarrowLow),
            [None, Some(View::NormalHigh), None, None]
        );
        assert!(!s.needed && !s.busy);
        // Once per run: later cycles ask for nothing, in play-on only a low view is put back.
        assert!(cycle(&mut s, 2, View::NarrowLow).iter().all(Option::is_none));
        assert_eq!(s.synchronize(true), Some(View::NormalHigh));
        s.sense(1, View::NormalHigh);
        assert_eq!(s.synchronize(true), None);
    }

    #[test]
    fn synchronous_phases_come_from_the_connection() {
        // Connections are taken at the thinks (80, 180 and 280 ms into the
        // period), so the phase is 2, 0 or 3: never the late phase 1.
        let mut seen = [0; 4];
        for a in offsets() {
            let phases = phases_at_kick_off([a; NUM_PLAYERS], ServerTimer::Synchronous);
            assert!(phases.iter().all(|&p| p == phases[0]));
            seen[usize::from(phases[0].0)] += 1;
            let expected = match a {
                0..=80 => 2,
                81..=180 => 0,
                181..=280 => 3,
                _ => 2,
            };
            assert_eq!(phases[0], SeePhase(expected), "offset {a} ms");
        }
        assert_eq!(seen[1], 0);
        assert!(seen[0] > 0 && seen[2] > 0 && seen[3] > 0);
    }
}
