//! The compiled net: input and output arcs per transition, consumers per place.

use super::{Marking, NodeRef, PetriNet, PlaceId, TokenOverflow, TransitionId};

/// A weighted connection from a transition's point of view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Arc {
    /// The place at the other end.
    pub(crate) place: PlaceId,
    /// Tokens moved.
    pub(crate) weight: u8,
}

/// Pre- and post-sets of every transition, and the transitions reading each place.
#[derive(Debug, Clone)]
pub struct Incidence {
    inputs: Vec<Vec<Arc>>,
    outputs: Vec<Vec<Arc>>,
    consumers: Vec<Vec<(TransitionId, u8)>>,
}

impl Incidence {
    /// Compiles `net`.
    pub fn new(net: &PetriNet) -> Self {
        let mut inputs = vec![Vec::new(); net.transitions().len()];
        let mut outputs = vec![Vec::new(); net.transitions().len()];
        let mut consumers = vec![Vec::new(); net.places().len()];
        for arc in net.arcs() {
            match (arc.source, arc.target) {
                (NodeRef::Place(p), NodeRef::Transition(t)) => {
                    inputs[t.index()].push(Arc {
                        place: p,
                        weight: arc.weight,
                    });
                    consumers[p.index()].push((t, arc.weight));
                }
                (NodeRef::Transition(t), NodeRef::Place(p)) => {
                    outputs[t.index()].push(Arc {
                        place: p,
                        weight: arc.weight,
                    });
                }
                // PetriNet::new refuses arcs between nodes of one kind.
                _ => {}
            }
        }
        Incidence {
            inputs,
            outputs,
            consumers,
        }
    }

    /// Number of transitions.
    pub(crate) fn transition_count(&self) -> usize {
        self.inputs.len()
    }

    /// Number of places.
    pub(crate) fn place_count(&self) -> usize {
        self.consumers.len()
    }

    /// The input arcs of `t`.
    #[inline]
    pub(crate) fn inputs(&self, t: TransitionId) -> &[Arc] {
        &self.inputs[t.index()]
    }

    /// The output arcs of `t`.
    #[inline]
    pub(crate) fn outputs(&self, t: TransitionId) -> &[Arc] {
        &self.outputs[t.index()]
    }

    /// The transitions with an input arc from `p`, with its weight.
    #[inline]
    pub(crate) fn consumers(&self, p: PlaceId) -> &[(TransitionId, u8)] {
        &self.consumers[p.index()]
    }

    /// Whether `t` has enough tokens in every input place (guards aside).
    #[inline]
    pub(crate) fn is_enabled(&self, marking: &Marking, t: TransitionId) -> bool {
        self.inputs(t).iter().all(|a| marking.get(a.place) >= a.weight)
    }

    /// Fires `t` in place: removes its input tokens, adds its output tokens.
    pub(crate) fn fire(&self, marking: &mut Marking, t: TransitionId) -> Result<(), TokenOverflow> {
        for a in self.inputs(t) {
            marking.remove(a.place, a.weight);
        }
        for a in self.outputs(t) {
            marking.add(a.place, a.weight)?;
        }
        Ok(())
    }

    /// Every transition in index order.
    pub(crate) fn transition_ids(&self) -> impl Iterator<Item = TransitionId> {
        (0..self.inputs.len()).map(TransitionId::new)
    }
}
