//! What goes wrong generating a plan: every error names the input's line and token.

/// A plan, a set of execution rules or a conditional plan that cannot be
/// turned into a Petri Net Plan.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GenerateError {
    /// A line of a plan that is not an action.
    #[error("line {line}: '{token}' is not an action: {expected}")]
    BadStep {
        /// 1-based line of the input.
        line: usize,
        /// The text that was read.
        token: String,
        /// What was expected there.
        expected: &'static str,
    },
    /// A name that cannot be an action's name in a plan's labels.
    #[error(
        "line {line}: '{name}' cannot name an action: a name starts with a letter and has only letters, digits, '_' and '-'"
    )]
    BadName {
        /// 1-based line of the input.
        line: usize,
        /// The name.
        name: String,
    },
    /// A timeout (`action|seconds`) that is not a positive whole number.
    #[error("line {line}: '{token}': the timeout after '|' must be a positive whole number of seconds")]
    BadTimeout {
        /// 1-based line of the input.
        line: usize,
        /// The step as written.
        token: String,
    },
    /// No plan was given.
    #[error("no plan to generate from: give at least one plan")]
    NoPlans,
    /// An execution rule that is not `*if* COND *during* ACTION *do* RECOVERY`.
    #[error("rule line {line}: '{text}': {expected}")]
    BadRule {
        /// 1-based line of the rules.
        line: usize,
        /// The line as written.
        text: String,
        /// What was expected.
        expected: String,
    },
    /// A rule for an action the plan does not have.
    #[error("rule line {line}: the plan has no action '{action}' (its actions: {known})")]
    UnknownRuleAction {
        /// 1-based line of the rules.
        line: usize,
        /// The action the rule names.
        action: String,
        /// The plan's actions, comma-separated.
        known: String,
    },
    /// A rule whose condition tests an atom the world does not have.
    #[error("rule line {line}: the atom '{atom}' is not one of the plan's atoms ({known})")]
    UnknownRuleAtom {
        /// 1-based line of the rules.
        line: usize,
        /// The atom.
        atom: String,
        /// The atoms allowed, comma-separated.
        known: String,
    },
    /// A conditional plan that does not read.
    #[error("conditional plan: {message} at '{token}'")]
    BadConditional {
        /// What was wrong.
        message: String,
        /// The offending token.
        token: String,
    },
}
