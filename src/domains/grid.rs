//! What the grid worlds share: compass moves and the move action.

use crate::executor::{OneStep, Registry, World};

/// A compass move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    /// North (up).
    North,
    /// South (down).
    South,
    /// East (right).
    East,
    /// West (left).
    West,
}

impl Direction {
    /// All four, in the order the plans list them.
    pub const ALL: [Direction; 4] = [Direction::North, Direction::South, Direction::East, Direction::West];

    /// The action name in the plans (`MoveNorth`, ...).
    pub(crate) fn action_name(self) -> &'static str {
        match self {
            Direction::North => "MoveNorth",
            Direction::South => "MoveSouth",
            Direction::East => "MoveEast",
            Direction::West => "MoveWest",
        }
    }

    /// The two perpendicular directions.
    pub(crate) fn perpendicular(self) -> [Direction; 2] {
        match self {
            Direction::North | Direction::South => [Direction::East, Direction::West],
            Direction::East | Direction::West => [Direction::North, Direction::South],
        }
    }
}

/// A world in which an agent moves.
pub(crate) trait Mover {
    /// Attempts one move (the world applies its own dynamics and rewards).
    fn apply_move(&mut self, direction: Direction);
}

/// The four moves, each a one-step action named as the plans name it.
pub(crate) fn registry<W: Mover + World + 'static>() -> Registry<W> {
    let mut r = Registry::new();
    for d in Direction::ALL {
        r.action(d.action_name(), &[], move |_| {
            OneStep::new(move |w: &mut W| w.apply_move(d))
        });
    }
    r
}
