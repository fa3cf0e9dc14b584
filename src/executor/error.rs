//! Why a plan cannot be executed.

/// An executor that cannot be built or cannot take a step.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ExecError {
    /// No registered action or sub-plan provides a name the plan uses.
    #[error("plan '{plan}': no action or sub-plan is registered for '{action}' (registered: {registered})")]
    UnknownAction {
        /// The plan naming it.
        plan: String,
        /// The action name.
        action: String,
        /// What the registry provides, comma-separated (`learnpnp domain NAME` lists them).
        registered: String,
    },
    /// A guard asks an action for a condition it does not declare.
    #[error("plan '{plan}': action '{action}' declares no internal condition '{condition}' (it declares: {declared})")]
    UndeclaredCondition {
        /// The plan.
        plan: String,
        /// The action.
        action: String,
        /// The condition asked for.
        condition: String,
        /// What the action declares, comma-separated.
        declared: String,
    },
    /// A sub-plan calls itself, directly or through others.
    #[error("plan '{plan}' calls itself through its sub-plans")]
    RecursiveSubPlan {
        /// The plan on the cycle.
        plan: String,
    },
    /// A place would exceed 255 tokens.
    #[error("plan '{plan}': place '{place}' would hold more than 255 tokens")]
    TokenOverflow {
        /// The plan.
        plan: String,
        /// The place id.
        place: String,
    },
    /// A conflict has more maximal non-conflicting sets than the executor enumerates.
    #[error("plan '{plan}': a conflict has more than {limit} alternative firing sets")]
    TooManyOptions {
        /// The plan.
        plan: String,
        /// The limit.
        limit: usize,
    },
    /// The chooser returned an index outside the options.
    #[error("plan '{plan}': the chooser picked option {index} of {count}")]
    InvalidChoice {
        /// The plan.
        plan: String,
        /// The index returned.
        index: usize,
        /// How many options there were.
        count: usize,
    },
}
