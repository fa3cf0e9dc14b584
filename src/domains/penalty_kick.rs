//! The penalty kick (thesis Figures 3.6, 5.2 - 5.6): a robot faces the goal
//! with the ball in front of it. Walking straight then kicking scores 10;
//! turning first makes the kick miss, which pays 0 after a timeout.
//!
//! In the plain plan both choices reach the same Kick marking, so methods that
//! bootstrap from the next marking cannot tell them apart; the tree and
//! memory-place plans make the markings differ (chapter 5.5).

use std::sync::Arc;

use super::task::{EpisodeWorld, PlanTask, TaskError, root_key};
use crate::executor::{Action, OneStep, Registry};
use crate::learning::Learner;
use crate::net::{NetError, PetriNet};
use crate::plan::{AllowedAtoms, Plan, catalog};

/// Which plan drives the kick.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Variant {
    /// Figure 3.6: both choices lead to one Kick marking.
    #[default]
    Plain,
    /// Figure 5.3: Kick duplicated after each choice.
    Tree,
    /// Figure 5.4: memory places record the choice.
    Memory,
    /// Figure 3.6 as a plan schema (`plans/penalty_kick.schema`): one Kick state.
    Schema,
    /// Figure 3.7 as a plan schema (`plans/penalty_kick_restructured.schema`):
    /// a Kick state after each choice.
    SchemaRestructured,
}

/// The plan schema of Figure 3.6, as shipped.
const SCHEMA: &str = include_str!("../../plans/penalty_kick.schema");
/// The plan schema of Figure 3.7, as shipped.
const SCHEMA_RESTRUCTURED: &str = include_str!("../../plans/penalty_kick_restructured.schema");

crate::named::impl_named!(
    Variant,
    "variant",
    [
        Plain => "plain",
        Tree => "tree",
        Memory => "memory",
        Schema => "schema",
        SchemaRestructured => "schema-restructured",
    ]
);

impl Variant {
    /// The variant's Petri Net Plan; `None` for the plan schemas (see [`plan`]).
    pub fn net(self) -> Option<Result<PetriNet, NetError>> {
        match self {
            Variant::Plain => Some(catalog::penalty_kick_plain()),
            Variant::Tree => Some(catalog::penalty_kick_tree()),
            Variant::Memory => Some(catalog::penalty_kick_memory()),
            Variant::Schema | Variant::SchemaRestructured => None,
        }
    }

    /// The markings whose values are traced: the afterstates of the first choice.
    fn traced_labels(self) -> [(&'static str, Vec<&'static str>); 2] {
        match self {
            Variant::Memory => [
                ("WalkStraight", vec!["WalkStraight.exec", "walked"]),
                ("Turn", vec!["Turn.exec", "turned"]),
            ],
            Variant::Schema | Variant::SchemaRestructured => [
                ("WalkStraight", vec!["[start, -, {true}: walk]"]),
                ("Turn", vec!["[start, -, {true}: turn]"]),
            ],
            _ => [("WalkStraight", vec!["WalkStraight.exec"]), ("Turn", vec!["Turn.exec"])],
        }
    }
}

/// The kick's parameters.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PenaltyKickConfig {
    /// The plan variant.
    pub variant: Variant,
    /// Reward of a goal.
    pub goal_reward: f64,
    /// Steps a missed kick takes before its timeout.
    pub miss_timeout: u32,
}

impl Default for PenaltyKickConfig {
    fn default() -> Self {
        PenaltyKickConfig {
            variant: Variant::Plain,
            goal_reward: 10.0,
            miss_timeout: 5,
        }
    }
}

/// The pitch as the plan's world.
#[derive(Debug, Default)]
pub struct Pitch {
    facing_goal: bool,
    pending: f64,
    ret: f64,
    actions: u32,
    goal_reward: f64,
    miss_timeout: u32,
}

reward_only_world!(Pitch);

impl Pitch {
    /// WalkStraight (keeps facing the goal) or Turn (faces away): one step each.
    fn orient(&mut self, keeps_facing: bool) {
        self.facing_goal &= keeps_facing;
        self.actions += 1;
    }
}

impl EpisodeWorld for Pitch {
    fn begin(&mut self) {
        self.facing_goal = true;
        self.pending = 0.0;
        self.ret = 0.0;
        self.actions = 0;
    }
    fn step_limit(&self) -> u32 {
        200
    }
    fn ret(&self) -> f64 {
        self.ret
    }
    fn actions(&self) -> u32 {
        self.actions
    }
}

/// Kick: scores at once when facing the goal, otherwise misses after a timeout.
#[derive(Default)]
struct Kick {
    elapsed: u32,
    done: bool,
}

impl Action<Pitch> for Kick {
    fn reset(&mut self) {
        *self = Kick::default();
    }
    fn start(&mut self, _: &mut Pitch) {
        *self = Kick::default();
    }
    fn step(&mut self, p: &mut Pitch) {
        if self.done {
            return;
        }
        self.elapsed += 1;
        if p.facing_goal {
            p.pending += p.goal_reward;
            p.ret += p.goal_reward;
            self.done = true;
        } else if self.elapsed >= p.miss_timeout {
            self.done = true;
        }
        if self.done {
            p.actions += 1;
        }
    }
    fn finished(&self, _: &Pitch) -> bool {
        self.done
    }
}

/// The actions of the kick.
pub fn registry() -> Registry<Pitch> {
    let mut r = Registry::new();
    r.action("WalkStraight", &[], |_| OneStep::new(|p: &mut Pitch| p.orient(true)));
    r.action("Turn", &[], |_| OneStep::new(|p: &mut Pitch| p.orient(false)));
    r.action("Kick", &[], |_| Kick::default());
    r
}

/// The variant's plan (a plan schema's constructed process for the schema variants).
pub fn plan(variant: Variant) -> Result<Plan, TaskError> {
    let schema_text = match variant.net() {
        Some(net) => {
            let net = net.map_err(crate::plan::PlanError::from)?;
            return Ok(Plan::from_net(net, AllowedAtoms::Open)?);
        }
        None if variant == Variant::Schema => SCHEMA,
        None => SCHEMA_RESTRUCTURED,
    };
    let invalid = |e: crate::schema::SchemaError| TaskError::Invalid(format!("the shipped schema: {e}"));
    let schema = crate::schema::parse_schema(schema_text).map_err(invalid)?;
    Ok(crate::schema::DecisionProcess::new(&schema, AllowedAtoms::Open)
        .map_err(invalid)?
        .into_plan())
}

/// Learning runs of the penalty kick.
pub type PenaltyKick = PlanTask<Pitch>;

impl PenaltyKick {
    /// A run of `plan` with `learner`.
    pub fn new(config: PenaltyKickConfig, plan: Arc<Plan>, learner: Box<dyn Learner>) -> Result<Self, TaskError> {
        let traced = config
            .variant
            .traced_labels()
            .into_iter()
            .filter_map(|(name, labels)| root_key(&plan, &labels).map(|key| (name.to_string(), key)))
            .collect();
        let pitch = Pitch {
            goal_reward: config.goal_reward,
            miss_timeout: config.miss_timeout,
            ..Pitch::default()
        };
        PlanTask::with(plan, &registry(), learner, pitch, traced)
    }
}
