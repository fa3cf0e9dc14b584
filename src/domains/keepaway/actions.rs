//! The keeper's actions: each issues the cycle's primitive command from the
//! framework's skills, and finishes when the situation it serves is over.

use crate::executor::{Action, Registry};
use learnpnp_keepaway::geometry::Vec2;
use learnpnp_keepaway::keeper::KeeperAction;
use learnpnp_keepaway::positions::PositioningPoint;
use learnpnp_keepaway::skills::pass::PassState;
use learnpnp_keepaway::skills::{get_open_from, go_to_support_point, hold_ball, intercept};

use super::world::KeeperWorld;

/// Keeps the ball for one cycle (the framework's hold, ratio 0.7).
#[derive(Debug, Default)]
struct Hold {
    done: bool,
}

impl Action<KeeperWorld> for Hold {
    fn reset(&mut self) {
        self.done = false;
    }
    fn start(&mut self, _: &mut KeeperWorld) {
        self.done = false;
    }
    fn step(&mut self, w: &mut KeeperWorld) {
        if self.done {
            return;
        }
        if let Some(view) = w.view().copied().filter(|_| w.has_ball()) {
            w.issue(hold_ball(&view, &w.config, w.config.skills.keeper_hold_ratio));
        }
        self.done = true;
    }
    fn finished(&self, _: &KeeperWorld) -> bool {
        self.done
    }
}

/// Which teammate a pass goes to.
#[derive(Debug, Clone, Copy)]
enum Receiver {
    /// The k-th closest teammate (1 or 2).
    Closest(usize),
    /// The teammate whose pass line is farthest from the takers (the thesis's simple policy).
    SafestLane,
}

/// Kicks the ball to a teammate, over several cycles if one kick cannot reach
/// the speed; finished once the ball has left the kickable range.
#[derive(Debug)]
struct Pass {
    receiver: Receiver,
    state: Option<PassState>,
    done: bool,
}

impl Pass {
    fn new(receiver: Receiver) -> Self {
        Pass {
            receiver,
            state: None,
            done: false,
        }
    }
}

impl Action<KeeperWorld> for Pass {
    fn reset(&mut self) {
        self.state = None;
        self.done = false;
    }
    fn start(&mut self, w: &mut KeeperWorld) {
        self.done = false;
        self.state = w.view().map(|view| {
            let rank = match self.receiver {
                Receiver::Closest(k) => k,
                Receiver::SafestLane => match w.distances() {
                    Some(d) if d.line[1] > d.line[0] => 2,
                    _ => 1,
                },
            };
            PassState::new(rank, view)
        });
    }
    fn step(&mut self, w: &mut KeeperWorld) {
        match (self.state.as_mut(), w.view().copied()) {
            (Some(pass), Some(view)) if w.has_ball() && !self.done => {
                let command = pass.kick(&view, &w.config);
                w.issue(command);
            }
            _ => self.done = true,
        }
    }
    fn finished(&self, _: &KeeperWorld) -> bool {
        self.done
    }
}

/// Goes for the ball while this keeper is the fastest to it.
#[derive(Debug, Default)]
struct Intercept;

impl Action<KeeperWorld> for Intercept {
    fn step(&mut self, w: &mut KeeperWorld) {
        if self.finished(w) {
            return;
        }
        if let Some(view) = w.view().copied() {
            let config = w.config;
            let command = intercept(&view, &config, w.intercept_memory());
            w.issue(command);
        }
    }
    fn finished(&self, w: &KeeperWorld) -> bool {
        w.has_ball() || !w.fastest()
    }
}

/// Where a supporting keeper goes.
#[derive(Debug, Clone, Copy)]
enum Support {
    /// The framework's get-open.
    GetOpen,
    /// A fixed point (thesis Figure 7.4).
    Point(Vec2),
}

/// Supports while another keeper is closer to the ball.
#[derive(Debug)]
struct Supporting {
    how: Support,
}

impl Action<KeeperWorld> for Supporting {
    fn step(&mut self, w: &mut KeeperWorld) {
        if self.finished(w) {
            return;
        }
        let Some(view) = w.view().copied() else { return };
        let command = match self.how {
            Support::GetOpen => {
                let Some(from) = w.pass_origin() else { return };
                get_open_from(&view, &w.config, from)
            }
            Support::Point(p) => go_to_support_point(&view, &w.config, p),
        };
        w.issue(command);
    }
    fn finished(&self, w: &KeeperWorld) -> bool {
        w.has_ball() || w.fastest()
    }
}

/// The plan name of a keeper's decision.
pub fn decision_name(action: KeeperAction) -> &'static str {
    match action {
        KeeperAction::Hold => "Hold",
        KeeperAction::Pass1 => "Pass1",
        KeeperAction::Pass2 => "Pass2",
    }
}

/// The plan name of the action going to a positioning point (`GoToCorner1`, ...).
pub fn goto_name(point: PositioningPoint) -> String {
    format!("GoTo{point:?}")
}

/// Every keeper action: `Hold`, `Pass1`, `Pass2`, `PassSafest`, `Intercept`,
/// `GetOpen` and `GoTo<point>` for the nine positioning points.
pub fn registry(config: &learnpnp_keepaway::params::KeepawayConfig) -> Registry<KeeperWorld> {
    let mut r = Registry::new();
    r.action("Hold", &[], |_| Hold::default());
    r.action("Pass1", &[], |_| Pass::new(Receiver::Closest(1)));
    r.action("Pass2", &[], |_| Pass::new(Receiver::Closest(2)));
    r.action("PassSafest", &[], |_| Pass::new(Receiver::SafestLane));
    r.action("Intercept", &[], |_| Intercept);
    r.action("GetOpen", &[], |_| Supporting { how: Support::GetOpen });
    for point in PositioningPoint::ALL {
        let at = point.point(&config.region);
        r.action(&goto_name(point), &[], move |_| Supporting {
            how: Support::Point(at),
        });
    }
    r
}
