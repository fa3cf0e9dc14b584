//! The net as a plan file describes it: nodes with ids and labels, weighted arcs.

use std::collections::{HashMap, HashSet};

use serde::{Deserialize, Serialize};

use super::Marking;
use super::ids::{PlaceId, TransitionId};

/// Where an editor drew a node (no meaning for execution; kept for round trips).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Position {
    /// Horizontal coordinate.
    pub x: f64,
    /// Vertical coordinate.
    pub y: f64,
}

/// A place: file id, label and initial tokens.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlaceNode {
    /// The element id in the file (`p1`); unique among all nodes.
    pub id: String,
    /// The label (`goto.exec`, `goal`, ...); two places may share one.
    pub label: String,
    /// Tokens in the initial marking.
    pub initial: u8,
    /// Drawing position, if the file had one.
    pub position: Option<Position>,
}

/// A transition: file id and label.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TransitionNode {
    /// The element id in the file (`t1`); unique among all nodes.
    pub id: String,
    /// The label (`goto.start [free]`, ...).
    pub label: String,
    /// Drawing position, if the file had one.
    pub position: Option<Position>,
}

/// One end of an arc.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum NodeRef {
    /// A place.
    Place(PlaceId),
    /// A transition.
    Transition(TransitionId),
}

/// A weighted arc between a place and a transition (either direction).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArcNode {
    /// The element id in the file.
    pub id: String,
    /// Source node.
    pub source: NodeRef,
    /// Target node.
    pub target: NodeRef,
    /// Tokens moved (at least 1).
    pub weight: u8,
}

/// A net that cannot exist: the message names the element id and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NetError {
    /// Two nodes (or two arcs) share an id.
    #[error("duplicate id '{id}'")]
    DuplicateId {
        /// The repeated id.
        id: String,
    },
    /// An arc names a node that does not exist.
    #[error("arc '{arc}': {end} '{node}' is not a place or transition of the net")]
    DanglingArc {
        /// The arc id.
        arc: String,
        /// `source` or `target`.
        end: &'static str,
        /// The missing node id.
        node: String,
    },
    /// An arc joins two places or two transitions.
    #[error(
        "arc '{arc}' joins two {kind}s ('{source_id}' -> '{target_id}'); an arc must join a place and a transition"
    )]
    SameKindArc {
        /// The arc id.
        arc: String,
        /// `place` or `transition`.
        kind: &'static str,
        /// Its source id.
        source_id: String,
        /// Its target id.
        target_id: String,
    },
    /// Two arcs join the same pair of nodes in the same direction.
    #[error("arc '{arc}' repeats an arc from '{source_id}' to '{target_id}'")]
    RepeatedArc {
        /// The second arc's id.
        arc: String,
        /// Its source id.
        source_id: String,
        /// Its target id.
        target_id: String,
    },
    /// An arc of weight zero.
    #[error("arc '{arc}' has weight 0")]
    ZeroWeight {
        /// The arc id.
        arc: String,
    },
}

/// A place/transition net with the ids and labels of its file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PetriNet {
    name: String,
    places: Vec<PlaceNode>,
    transitions: Vec<TransitionNode>,
    arcs: Vec<ArcNode>,
}

/// An arc given by node ids, before they are resolved.
pub(crate) type ArcSpec<'a> = (&'a str, &'a str, &'a str, u8);

impl PetriNet {
    /// A net from its nodes and arcs given by node ids `(arc id, source id, target id, weight)`.
    pub fn new(
        name: impl Into<String>,
        places: Vec<PlaceNode>,
        transitions: Vec<TransitionNode>,
        arcs: &[ArcSpec<'_>],
    ) -> Result<Self, NetError> {
        let mut nodes: HashMap<&str, NodeRef> = HashMap::new();
        for (i, p) in places.iter().enumerate() {
            if nodes.insert(p.id.as_str(), NodeRef::Place(PlaceId::new(i))).is_some() {
                return Err(NetError::DuplicateId { id: p.id.clone() });
            }
        }
        for (i, t) in transitions.iter().enumerate() {
            if nodes
                .insert(t.id.as_str(), NodeRef::Transition(TransitionId::new(i)))
                .is_some()
            {
                return Err(NetError::DuplicateId { id: t.id.clone() });
            }
        }
        let mut arc_ids = HashSet::new();
        let mut pairs = HashSet::new();
        let mut resolved = Vec::with_capacity(arcs.len());
        for &(id, source, target, weight) in arcs {
            if !arc_ids.insert(id) || nodes.contains_key(id) {
                return Err(NetError::DuplicateId { id: id.to_string() });
            }
            let lookup = |end: &'static str, node: &str| {
                nodes.get(node).copied().ok_or_else(|| NetError::DanglingArc {
                    arc: id.to_string(),
                    end,
                    node: node.to_string(),
                })
            };
            let s = lookup("source", source)?;
            let t = lookup("target", target)?;
            let kind = match (s, t) {
                (NodeRef::Place(_), NodeRef::Place(_)) => Some("place"),
                (NodeRef::Transition(_), NodeRef::Transition(_)) => Some("transition"),
                _ => None,
            };
            if let Some(kind) = kind {
                return Err(NetError::SameKindArc {
                    arc: id.to_string(),
                    kind,
                    source_id: source.to_string(),
                    target_id: target.to_string(),
                });
            }
            if weight == 0 {
                return Err(NetError::ZeroWeight { arc: id.to_string() });
            }
            if !pairs.insert((s, t)) {
                return Err(NetError::RepeatedArc {
                    arc: id.to_string(),
                    source_id: source.to_string(),
                    target_id: target.to_string(),
                });
            }
            resolved.push(ArcNode {
                id: id.to_string(),
                source: s,
                target: t,
                weight,
            });
        }
        Ok(PetriNet {
            name: name.into(),
            places,
            transitions,
            arcs: resolved,
        })
    }

    /// The plan's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Renames the net.
    pub fn set_name(&mut self, name: impl Into<String>) {
        self.name = name.into();
    }

    /// The places, indexed by [`PlaceId`].
    pub fn places(&self) -> &[PlaceNode] {
        &self.places
    }

    /// The transitions, indexed by [`TransitionId`].
    pub fn transitions(&self) -> &[TransitionNode] {
        &self.transitions
    }

    /// The arcs in file order.
    pub fn arcs(&self) -> &[ArcNode] {
        &self.arcs
    }

    /// One place.
    pub(crate) fn place(&self, id: PlaceId) -> &PlaceNode {
        &self.places[id.index()]
    }

    /// One transition.
    pub fn transition(&self, id: TransitionId) -> &TransitionNode {
        &self.transitions[id.index()]
    }

    /// The file id of either kind of node.
    pub fn node_id(&self, node: NodeRef) -> &str {
        match node {
            NodeRef::Place(p) => &self.place(p).id,
            NodeRef::Transition(t) => &self.transition(t).id,
        }
    }

    /// The initial marking.
    pub(crate) fn initial_marking(&self) -> Marking {
        Marking::from_tokens(self.places.iter().map(|p| p.initial).collect())
    }

    /// The places with this exact label.
    pub fn places_labelled<'a>(&'a self, label: &'a str) -> impl Iterator<Item = PlaceId> + 'a {
        self.places
            .iter()
            .enumerate()
            .filter(move |(_, p)| p.label == label)
            .map(|(i, _)| PlaceId::new(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn place(id: &str) -> PlaceNode {
        PlaceNode {
            id: id.into(),
            label: id.into(),
            initial: 0,
            position: None,
        }
    }

    fn transition(id: &str) -> TransitionNode {
        TransitionNode {
            id: id.into(),
            label: id.into(),
            position: None,
        }
    }

    #[test]
    fn rejects_place_to_place_arc() {
        let err = PetriNet::new("n", vec![place("p1"), place("p2")], vec![], &[("a1", "p1", "p2", 1)]).unwrap_err();
        assert!(
            matches!(err, NetError::SameKindArc { ref arc, .. } if arc == "a1"),
            "{err}"
        );
        assert!(err.to_string().contains("a1"));
    }

    #[test]
    fn rejects_dangling_and_duplicate() {
        let err = PetriNet::new("n", vec![place("p1")], vec![transition("t1")], &[("a1", "p1", "t9", 1)]).unwrap_err();
        assert!(err.to_string().contains("t9"), "{err}");
        let err = PetriNet::new("n", vec![place("x")], vec![transition("x")], &[]).unwrap_err();
        assert_eq!(err, NetError::DuplicateId { id: "x".into() });
    }

    #[test]
    fn resolves_arcs() {
        let net = PetriNet::new(
            "n",
            vec![place("p1"), place("p2")],
            vec![transition("t1")],
            &[("a1", "p1", "t1", 1), ("a2", "t1", "p2", 2)],
        )
        .unwrap();
        assert_eq!(net.arcs()[1].target, NodeRef::Place(PlaceId::new(1)));
        assert_eq!(net.arcs()[1].weight, 2);
        assert_eq!(net.node_id(net.arcs()[0].source), "p1");
    }
}
