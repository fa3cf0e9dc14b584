//! Place/transition nets: the structure under every plan.
//!
//! [`PetriNet`](crate::net::PetriNet) is the net as a file describes it (ids, labels, arcs, weights,
//! initial marking); [`Incidence`](crate::net::Incidence) is its compiled form for firing; [`Marking`](crate::net::Marking)
//! is the token count of every place, the state key of every value table.

mod ids;
mod incidence;
mod marking;
mod petri_net;

pub use ids::{PlaceId, TransitionId};
pub use incidence::{Arc, Incidence};
pub use marking::{Marking, TokenOverflow};
pub use petri_net::{ArcNode, NetError, NodeRef, PetriNet, PlaceNode, Position, TransitionNode};
