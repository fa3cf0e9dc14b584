//! What a plan for each domain may use, from the domains' own registries and
//! atom tables: its actions and sub-plans, the atoms its guards may test, its
//! reward and when an episode ends (`learnpnp domains`, `learnpnp domain NAME`).

use std::fmt;

use super::keepaway::{self, KeepawayDomainConfig, KeepawayMode};
use super::nmdp::{self, NmdpConfig};
use super::parr_russell::{self, ParrRussellConfig};
use super::penalty_kick::{self, PenaltyKickConfig};
use super::sutton::{self, SuttonConfig};
use crate::executor::{Registered, RegisteredKind, Registry};

/// One domain, as a plan author needs it.
#[derive(Debug, Clone, PartialEq)]
pub struct DomainDescription {
    /// The command-line name (`learnpnp experiment NAME`).
    pub name: &'static str,
    /// What it is.
    pub(crate) about: String,
    /// The plan used unless `--plan FILE` replaces it, and who executes it.
    pub plan: String,
    /// The actions (and sub-plans) a plan may name, with their conditions.
    pub actions: Vec<Registered>,
    /// The atoms guards may test (besides the actions' internal conditions).
    pub atoms: Vec<String>,
    /// What an episode earns.
    pub reward: String,
    /// When an episode ends.
    pub(crate) episode_end: String,
}

fn entries<W>(registry: &Registry<W>) -> Vec<Registered> {
    registry.entries()
}

fn keepaway(name: &'static str, mode: KeepawayMode) -> DomainDescription {
    let config = KeepawayDomainConfig::for_mode(mode);
    let sim = config.simulator();
    let plan = match mode {
        KeepawayMode::Pass => {
            "plans/keepaway_pass.pnml (thesis 7.2), executed by keeper 1; keepers 2 and 3 follow the threshold policy"
        }
        KeepawayMode::Position => "plans/keepaway_position.pnml (thesis 7.3), executed by every keeper",
        KeepawayMode::Fixed(_) => "none: every keeper follows the fixed policy of --policy (nothing learns)",
    };
    DomainDescription {
        name,
        about: format!(
            "Keepaway 3 vs 2 in a {} m x {} m region (RoboCup soccer server physics, the keepaway framework's skills and takers)",
            sim.region.length, sim.region.width
        ),
        plan: plan.to_string(),
        actions: entries(&keepaway::registry(&sim)),
        atoms: keepaway::ATOMS.iter().map(|s| s.to_string()).collect(),
        reward: format!(
            "the time elapsed: {} s per {} ms cycle, so an episode's return is its duration in seconds",
            sim.server.cycle_seconds,
            (sim.server.cycle_seconds * 1000.0).round()
        ),
        episode_end: format!(
            "the ball leaves the region, or a taker holds it (within {} m) for {} consecutive cycles{}",
            sim.server.kickable_distance(),
            sim.referee.turnover_time(),
            if mode == KeepawayMode::Position {
                format!(
                    "; the ball holder passes when a taker is within {} m",
                    config.hold_threshold
                )
            } else {
                String::new()
            }
        ),
    }
}

/// Every domain of `learnpnp experiment`, in its order.
pub fn domains() -> Vec<DomainDescription> {
    let pr = ParrRussellConfig::default();
    let su = SuttonConfig::default();
    let pk = PenaltyKickConfig::default();
    vec![
        DomainDescription {
            name: "parr-russell",
            about: "Parr and Russell's 4 x 3 grid (thesis 6.1): moves go the intended way with probability \
                    0.8, each perpendicular way with 0.1; the agent sees only the walls west and east"
                .to_string(),
            plan: "plans/parr_russell.pnml (thesis 6.1)".to_string(),
            actions: entries(&parr_russell::registry()),
            atoms: parr_russell::ATOMS.iter().map(|s| s.to_string()).collect(),
            reward: format!(
                "{} per action; +1 on entering (4,3), -1 on entering (4,2)",
                pr.step_reward
            ),
            episode_end: format!("the agent enters (4,3) or (4,2), or after {} actions", pr.max_actions),
        },
        DomainDescription {
            name: "sutton",
            about: "Sutton's 9 x 6 grid (thesis 6.4): deterministic moves; the agent sees its eight \
                    neighbouring cells (blocked or not) and whether it is at the goal"
                .to_string(),
            plan: "plans/sutton.pnml (thesis 6.4)".to_string(),
            actions: entries(&sutton::registry()),
            atoms: sutton::atoms().names().map(str::to_string).collect(),
            reward: "-1 per action, 0 for the action entering the goal".to_string(),
            episode_end: format!(
                "the agent reaches the goal, or after {} actions; each episode starts in a random free cell",
                su.max_actions
            ),
        },
        DomainDescription {
            name: "penalty-kick",
            about: "The penalty kick (thesis Figures 3.6 and 5.2 - 5.6): a robot facing the goal walks \
                    straight or turns, then kicks"
                .to_string(),
            plan: "one of --variant plain | tree | memory (plans/penalty_kick_*.pnml) | schema | schema-restructured (plans/penalty_kick*.schema)".to_string(),
            actions: entries(&penalty_kick::registry()),
            atoms: Vec::new(),
            reward: format!(
                "{} when Kick scores (the robot still faces the goal); 0 when it misses, after {} steps",
                pk.goal_reward, pk.miss_timeout
            ),
            episode_end: "the plan reaches its goal marking (after Kick)".to_string(),
        },
        DomainDescription {
            name: "nmdp",
            about: "The small N-MDP of thesis Figure 4.3: A1 or B1 in the first state, A2 or B2 in the \
                    second (which does not tell the first choice); each of the four policies' returns is \
                    normally distributed"
                .to_string(),
            plan: "built in (S1 -> A1 | B1 -> S2 -> A2 | B2 -> goal)".to_string(),
            actions: entries(&nmdp::registry()),
            atoms: Vec::new(),
            reward: {
                let r = NmdpConfig::default().returns;
                format!(
                    "at the end, from N(mean, sd): A1-A2 N({}, {}), A1-B2 N({}, {}), B1-A2 N({}, {}), B1-B2 N({}, {})",
                    r[0][0].mean,
                    r[0][0].sd,
                    r[0][1].mean,
                    r[0][1].sd,
                    r[1][0].mean,
                    r[1][0].sd,
                    r[1][1].mean,
                    r[1][1].sd
                )
            },
            episode_end: "after the second choice".to_string(),
        },
        keepaway("keepaway-pass", KeepawayMode::Pass),
        keepaway("keepaway-position", KeepawayMode::Position),
        keepaway(
            "keepaway-fixed",
            KeepawayMode::Fixed(crate::domains::keepaway::FixedPolicy::Handcoded),
        ),
    ]
}

/// The domain called `name`, if there is one.
pub fn domain(name: &str) -> Option<DomainDescription> {
    domains().into_iter().find(|d| d.name == name)
}

/// What a domain's action does, for the listing.
fn action_about(name: &str) -> String {
    if let Some(point) = name.strip_prefix("GoTo") {
        return format!(
            "go to positioning point {point} (thesis Figure 7.4) while another keeper is closer to the ball"
        );
    }
    if let Some(direction) = name.strip_prefix("Move") {
        return format!("one move {} (one action)", direction.to_lowercase());
    }
    match name {
        "Hold" => "keep the ball for one cycle (the framework's hold)",
        "Pass1" => "pass to the closest teammate; ends when the ball has left",
        "Pass2" => "pass to the second-closest teammate; ends when the ball has left",
        "PassSafest" => "pass to the teammate whose lane the takers are farthest from",
        "Intercept" => "go for the ball while this keeper is the fastest to it",
        "GetOpen" => "get open for a pass (the framework's get-open) while another keeper is closer to the ball",
        "WalkStraight" => "walk to the ball keeping the goal ahead (one step)",
        "Turn" => "turn before walking to the ball (one step; the kick then misses)",
        "Kick" => "kick: scores if the robot faces the goal",
        "A1" | "B1" => "the first state's choice (one step; the second state does not tell it)",
        "A2" | "B2" => "the second state's choice (one step), then the policy's return is drawn",
        _ => "",
    }
    .to_string()
}

/// A multi-line description: plan, actions, what guards may test, reward, episode end.
impl fmt::Display for DomainDescription {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}: {}", self.name, self.about)?;
        writeln!(f, "  plan: {}", self.plan)?;
        writeln!(
            f,
            "  actions (a place labelled X.exec runs X; transitions X.start, X.end, X.interrupt, X.resume, X.fail call it):"
        )?;
        let width = self.actions.iter().map(|a| a.pattern().len()).max().unwrap_or(0);
        for a in &self.actions {
            let about = match a.kind {
                RegisteredKind::SubPlan => "a sub-plan".to_string(),
                _ => action_about(&a.name),
            };
            writeln!(f, "    {:<width$}  {about}", a.pattern())?;
        }
        let declared: Vec<String> = self
            .actions
            .iter()
            .flat_map(|a| a.conditions.iter().map(move |c| format!("{}.{c}", a.name)))
            .collect();
        let atoms = if self.atoms.is_empty() {
            "no atom of the world".to_string()
        } else {
            format!("the atoms {}", self.atoms.join(", "))
        };
        write!(f, "  guards may test: {atoms}; X.finished and X.failed of any action X")?;
        if !declared.is_empty() {
            write!(f, "; {}", declared.join(", "))?;
        }
        writeln!(f)?;
        writeln!(f, "  reward: {}", self.reward)?;
        writeln!(f, "  episode end: {}", self.episode_end)
    }
}
