//! Structural analysis of a plan: what `learnpnp check` reports.
//!
//! [`explore`] builds the graph of reachable markings with guards free (any
//! guard may be true or false), goal and fail markings terminal, and unbounded
//! places accelerated to ω (Karp–Miller), under a marking limit. [`check`]
//! derives from it the thesis's properties of a Petri Net Plan (section 2.3):
//! safety of execution places, minimality, effectiveness, and the absence of
//! dead markings, plus token bounds and choice points, in a [`CheckReport`].
//! Memory places and loop counters may exceed one token by design (thesis 5.5):
//! they are noted, not failed.

mod check;
mod choice;
mod count;
mod diagnosis;
mod guards;
mod options;
mod reachability;
mod report;

pub use check::check;
pub use choice::{ChoicePoint, choice_points, structural_choice_points};
pub use count::Count;
pub use guards::{MAX_GUARD_ATOMS, jointly_satisfiable};
pub use options::{ChoiceAt, before, choices_among, choices_at, option_label, option_transitions, transition_name};
pub use reachability::{DEFAULT_LIMIT, MEMORY_LIMIT, Reachability, StateId, explore, marking_limit};
pub use report::{
    CheckReport, Element, Example, Failure, Note, Outcome, PlaceBound, Property, ReportedChoice, Verdict,
};
