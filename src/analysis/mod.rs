//! Structural analysis of a plan: what `learnpnp check` reports.
//!
//! [`explore`](crate::analysis::explore) builds the graph of reachable markings with guards free (any
//! guard may be true or false), goal and fail markings terminal, and unbounded
//! places accelerated to ω (Karp–Miller), under a marking limit and a memory
//! limit ([`Limits`](crate::analysis::Limits)). Markings are stored sparsely, and the plan's
//! independent parts (an environment-tracking sub-net beside the procedure)
//! are explored apart and combined exactly ([`Exploration`](crate::analysis::Exploration)), so the cost
//! follows the tokens and the parts, not the places and their combinations.
//! [`check`](crate::analysis::check) explores once and derives from that one exploration the thesis's
//! properties of a Petri Net Plan (section 2.3): safety of execution places,
//! minimality, effectiveness, and the absence of dead markings, plus token
//! bounds and choice points, in a [`CheckReport`](crate::analysis::CheckReport).
//! Memory places and loop counters may exceed one token by design (thesis 5.5):
//! they are noted, not failed.

mod check;
mod choice;
mod choice_options;
mod count;
mod diagnosis;
mod exploration;
mod guards;
mod limits;
mod markings;
mod parts;
mod reachability;
mod report;

pub use check::{check, check_within};
pub use choice::{ChoicePoint, choice_points, structural_choice_points};
pub use choice_options::{
    ChoiceAt, before, choices_among, choices_at, option_label, option_transitions, transition_name,
};
pub use count::Count;
pub use exploration::{Exploration, explore, explore_within};
pub use guards::{MAX_GUARD_ATOMS, jointly_satisfiable};
pub use limits::{DEFAULT_LIMIT, Limits, MEMORY_LIMIT, Stop};
pub use reachability::{Reachability, StateId};
pub use report::{
    CheckReport, Element, Example, Failure, Note, Outcome, PlaceBound, Property, ReportedChoice, Verdict,
};
