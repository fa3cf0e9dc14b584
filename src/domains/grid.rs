//! What the grid worlds share: compass moves and the move action.

use crate::executor::Action;

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

/// A one-step action that moves the agent when stepped.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Move {
    direction: Direction,
    done: bool,
}

impl Move {
    /// The move in `direction`.
    pub(crate) fn new(direction: Direction) -> Self {
        Move { direction, done: false }
    }
}

impl<W: Mover> Action<W> for Move {
    fn reset(&mut self) {
        self.done = false;
    }
    fn start(&mut self, _: &mut W) {
        self.done = false;
    }
    fn step(&mut self, world: &mut W) {
        if !self.done {
            world.apply_move(self.direction);
            self.done = true;
        }
    }
    fn finished(&self, _: &W) -> bool {
        self.done
    }
}
