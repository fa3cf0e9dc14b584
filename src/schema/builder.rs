//! Building schemas in code: the same checks as the file reader, without line numbers.
//!
//! ```
//! use learnpnp::schema::SchemaBuilder;
//!
//! let mut b = SchemaBuilder::new();
//! b.machine("penalty_kick")
//!     .initial("start", &[])
//!     .state("walk", &["WalkStraight"])
//!     .state("turn", &["Turn"])
//!     .state("kick", &["Kick"])
//!     .final_state("scored")
//!     .edge("start", "walk", None, None)
//!     .edge("start", "turn", None, None)
//!     .edge("walk", "kick", Some("WalkStraight.finished"), None)
//!     .edge("turn", "kick", Some("Turn.finished"), None)
//!     .edge("kick", "scored", Some("Kick.finished"), None);
//! let schema = b.build()?;
//! assert_eq!(schema.root().states().len(), 5);
//! # Ok::<(), learnpnp::schema::SchemaError>(())
//! ```

use super::SchemaError;
use super::model::{Draft, DraftEdge, DraftMachine, DraftState, Schema, StateKind, validate};

/// The machine being built: add states and edges in any order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MachineBuilder {
    draft: DraftMachine,
}

impl MachineBuilder {
    fn push_state(&mut self, name: &str, actions: &[&str], initial: bool, kind: StateKind) -> &mut Self {
        self.draft.states.push(DraftState {
            name: name.to_string(),
            actions: actions.iter().map(|a| a.to_string()).collect(),
            initial,
            kind,
            line: None,
        });
        self
    }

    /// The initial state `name`, running `actions`.
    pub fn initial(&mut self, name: &str, actions: &[&str]) -> &mut Self {
        self.push_state(name, actions, true, StateKind::Ordinary)
    }

    /// An ordinary state `name`, running `actions`.
    pub fn state(&mut self, name: &str, actions: &[&str]) -> &mut Self {
        self.push_state(name, actions, false, StateKind::Ordinary)
    }

    /// A final state: entering it ends the machine (`M.finished`).
    pub fn final_state(&mut self, name: &str) -> &mut Self {
        self.push_state(name, &[], false, StateKind::Final)
    }

    /// A final state that ends the machine as failed (`M.failed`).
    pub fn failure_state(&mut self, name: &str) -> &mut Self {
        self.push_state(name, &[], false, StateKind::Failure)
    }

    /// An edge from `from` to `to`, triggered by `event` (`None`: the empty
    /// event) when `condition` holds (guard syntax; `None`: true).
    pub fn edge(&mut self, from: &str, to: &str, event: Option<&str>, condition: Option<&str>) -> &mut Self {
        self.draft.edges.push(DraftEdge {
            from: from.to_string(),
            to: to.to_string(),
            event: event.map(str::to_string),
            condition: condition.map(str::to_string),
            line: None,
        });
        self
    }
}

/// Builds a schema machine by machine; the first machine is the root.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SchemaBuilder {
    machines: Vec<MachineBuilder>,
}

impl SchemaBuilder {
    /// An empty schema.
    pub fn new() -> Self {
        Self::default()
    }

    /// Starts machine `name` and returns it to add states and edges.
    pub fn machine(&mut self, name: &str) -> &mut MachineBuilder {
        self.machines.push(MachineBuilder {
            draft: DraftMachine {
                name: name.to_string(),
                line: None,
                states: Vec::new(),
                edges: Vec::new(),
            },
        });
        let last = self.machines.len() - 1;
        &mut self.machines[last]
    }

    /// The schema, checked as a file would be.
    pub fn build(self) -> Result<Schema, SchemaError> {
        validate(Draft {
            machines: self.machines.into_iter().map(|m| m.draft).collect(),
        })
    }
}
