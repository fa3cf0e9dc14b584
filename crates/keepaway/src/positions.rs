//! The nine positioning points of the thesis's multi-agent experiment (Figure 7.4).
//!
//! The figure is not available as data; the points are chosen to match its text —
//! "corner 2 (the top-right corner)", "corner 3 (the bottom-right corner)",
//! "middle point 1 (the leftmost middle point)" — numbering corners clockwise from
//! the top-left and middle points clockwise from the left. They lie on the outer ring
//! of the framework's get-open grid (15% inside the region's border: ±7 m on a
//! 20 m region), so that a keeper there stays safely inside the region, plus the
//! centre. "Top" is +y (see [`crate::geometry`] on orientation).

use super::geometry::Vec2;
use super::params::Region;
use serde::{Deserialize, Serialize};

/// Fraction of the region left as a border around the points (the get-open grid's).
pub(crate) const POSITION_BORDER: f64 = 0.15;

/// A positioning point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum PositioningPoint {
    /// Corner 1: top-left.
    Corner1,
    /// Corner 2: top-right.
    Corner2,
    /// Corner 3: bottom-right.
    Corner3,
    /// Corner 4: bottom-left.
    Corner4,
    /// The centre.
    Centre,
    /// Middle point 1: left.
    Middle1,
    /// Middle point 2: top.
    Middle2,
    /// Middle point 3: right.
    Middle3,
    /// Middle point 4: bottom.
    Middle4,
}

impl PositioningPoint {
    /// All nine, in a fixed order (the index used by [`PositioningPoint::index`]).
    pub const ALL: [PositioningPoint; 9] = [
        PositioningPoint::Corner1,
        PositioningPoint::Corner2,
        PositioningPoint::Corner3,
        PositioningPoint::Corner4,
        PositioningPoint::Centre,
        PositioningPoint::Middle1,
        PositioningPoint::Middle2,
        PositioningPoint::Middle3,
        PositioningPoint::Middle4,
    ];

    /// Index in [`PositioningPoint::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// The point with index `i`, if `i < 9`.
    pub fn from_index(i: usize) -> Option<PositioningPoint> {
        Self::ALL.get(i).copied()
    }

    /// Coordinates on `region` (for 20 x 20: corners (±7, ±7), middles (±7, 0) and
    /// (0, ±7), centre (0, 0)).
    pub fn point(self, region: &Region) -> Vec2 {
        let x = region.half_length() - POSITION_BORDER * region.length;
        let y = region.half_width() - POSITION_BORDER * region.width;
        match self {
            PositioningPoint::Corner1 => Vec2::new(-x, y),
            PositioningPoint::Corner2 => Vec2::new(x, y),
            PositioningPoint::Corner3 => Vec2::new(x, -y),
            PositioningPoint::Corner4 => Vec2::new(-x, -y),
            PositioningPoint::Centre => Vec2::ZERO,
            PositioningPoint::Middle1 => Vec2::new(-x, 0.0),
            PositioningPoint::Middle2 => Vec2::new(0.0, y),
            PositioningPoint::Middle3 => Vec2::new(x, 0.0),
            PositioningPoint::Middle4 => Vec2::new(0.0, -y),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_points() {
        let r = Region::default();
        assert_eq!(PositioningPoint::Corner2.point(&r), Vec2::new(7.0, 7.0));
        assert_eq!(PositioningPoint::Corner3.point(&r), Vec2::new(7.0, -7.0));
        assert_eq!(PositioningPoint::Middle1.point(&r), Vec2::new(-7.0, 0.0));
        for (i, p) in PositioningPoint::ALL.iter().enumerate() {
            assert_eq!(p.index(), i);
            assert_eq!(PositioningPoint::from_index(i), Some(*p));
        }
        assert_eq!(PositioningPoint::from_index(9), None);
    }
}
