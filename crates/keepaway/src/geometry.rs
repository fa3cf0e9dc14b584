//! Plane geometry for the simulator.
//!
//! Conventions, used everywhere in [`crate`]:
//! - coordinates in metres, x to the right, y up (mathematical orientation; note that
//!   the soccer monitor draws +y downwards, which only matters when reading figures);
//! - **angles in degrees**, as in the soccer server's protocol and the keepaway
//!   framework, measured counter-clockwise from +x and normalised to `(-180, 180]`.

use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};
use std::sync::LazyLock;

/// A 2-D vector (position, velocity or acceleration), in metres.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vec2 {
    /// x coordinate.
    pub x: f64,
    /// y coordinate.
    pub y: f64,
}

impl Vec2 {
    /// The zero vector.
    pub const ZERO: Vec2 = Vec2 { x: 0.0, y: 0.0 };

    /// A vector from its coordinates.
    pub const fn new(x: f64, y: f64) -> Self {
        Vec2 { x, y }
    }

    /// A vector of length `r` pointing at `deg` degrees.
    pub fn polar(r: f64, deg: f64) -> Self {
        let (s, c) = deg.to_radians().sin_cos();
        Vec2 { x: r * c, y: r * s }
    }

    /// Euclidean length (a plain square root: coordinates here are far from
    /// overflow, and `hypot` is several times slower).
    pub fn norm(self) -> f64 {
        self.norm_sq().sqrt()
    }

    /// Squared length.
    pub(crate) fn norm_sq(self) -> f64 {
        self.x * self.x + self.y * self.y
    }

    /// Distance to `other`.
    pub fn dist(self, other: Vec2) -> f64 {
        (self - other).norm()
    }

    /// Squared distance to `other`.
    pub(crate) fn dist_sq(self, other: Vec2) -> f64 {
        (self - other).norm_sq()
    }

    /// Direction in degrees, `(-180, 180]`; 0 for the zero vector.
    pub fn dir(self) -> f64 {
        if self.x == 0.0 && self.y == 0.0 {
            0.0
        } else {
            self.y.atan2(self.x).to_degrees()
        }
    }

    /// Dot product.
    pub fn dot(self, other: Vec2) -> f64 {
        self.x * other.x + self.y * other.y
    }

    /// z component of the cross product (`self.x * other.y - self.y * other.x`).
    pub(crate) fn cross(self, other: Vec2) -> f64 {
        self.x * other.y - self.y * other.x
    }

    /// This vector rotated counter-clockwise by `deg` degrees.
    pub(crate) fn rotate(self, deg: f64) -> Self {
        self.rotate_by(deg.to_radians().sin_cos())
    }

    /// This vector rotated counter-clockwise by the angle whose sine and cosine
    /// are `(s, c)`, for several vectors turned by one angle.
    pub(crate) fn rotate_by(self, (s, c): (f64, f64)) -> Self {
        Vec2 {
            x: self.x * c - self.y * s,
            y: self.x * s + self.y * c,
        }
    }

    /// This vector scaled to length `r` (the zero vector stays zero).
    pub fn with_norm(self, r: f64) -> Self {
        let n = self.norm();
        if n > 0.0 { self * (r / n) } else { Vec2::ZERO }
    }

    /// Whether both coordinates are finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

impl Add for Vec2 {
    type Output = Vec2;
    fn add(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x + o.x, self.y + o.y)
    }
}

impl Sub for Vec2 {
    type Output = Vec2;
    fn sub(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x - o.x, self.y - o.y)
    }
}

impl Neg for Vec2 {
    type Output = Vec2;
    fn neg(self) -> Vec2 {
        Vec2::new(-self.x, -self.y)
    }
}

impl Mul<f64> for Vec2 {
    type Output = Vec2;
    fn mul(self, k: f64) -> Vec2 {
        Vec2::new(self.x * k, self.y * k)
    }
}

impl Div<f64> for Vec2 {
    type Output = Vec2;
    fn div(self, k: f64) -> Vec2 {
        Vec2::new(self.x / k, self.y / k)
    }
}

impl AddAssign for Vec2 {
    fn add_assign(&mut self, o: Vec2) {
        self.x += o.x;
        self.y += o.y;
    }
}

impl SubAssign for Vec2 {
    fn sub_assign(&mut self, o: Vec2) {
        self.x -= o.x;
        self.y -= o.y;
    }
}

impl MulAssign<f64> for Vec2 {
    fn mul_assign(&mut self, k: f64) {
        self.x *= k;
        self.y *= k;
    }
}

/// Sine and cosine of `deg` degrees, `deg.to_radians().sin_cos()` bit for bit,
/// for angles that are mostly whole degrees (the body sense's): whole degrees in
/// `[-180, 180]` are read from a table of those very values; negative zero and
/// everything else is computed.
pub(crate) fn sin_cos_deg(deg: f64) -> (f64, f64) {
    // Saturating; the bit comparison keeps only exact whole degrees.
    let whole = deg as i32;
    if (-180..=180).contains(&whole) && f64::from(whole).to_bits() == deg.to_bits() {
        WHOLE_DEGREE_SIN_COS[usize::try_from(whole + 180).unwrap_or(0)]
    } else {
        deg.to_radians().sin_cos()
    }
}

/// `sin_cos` of every whole degree in `[-180, 180]`, indexed by degree + 180.
static WHOLE_DEGREE_SIN_COS: LazyLock<[(f64, f64); 361]> = LazyLock::new(|| {
    let mut table = [(0.0, 0.0); 361];
    for (deg, entry) in (-180i32..).zip(table.iter_mut()) {
        *entry = f64::from(deg).to_radians().sin_cos();
    }
    table
});

/// `deg` normalised to `(-180, 180]` (non-finite input gives NaN, never a hang).
pub fn normalize_deg(deg: f64) -> f64 {
    if deg > -180.0 && deg <= 180.0 {
        return deg;
    }
    let r = deg - 360.0 * (deg / 360.0).round();
    if r <= -180.0 {
        r + 360.0
    } else if r > 180.0 {
        r - 360.0
    } else {
        r
    }
}

/// `v` limited to `[lo, hi]`; unlike `f64::clamp` it never panics (with `lo > hi`
/// or NaN bounds the result is simply `min(max(v, lo), hi)`).
pub(crate) fn clamp(v: f64, lo: f64, hi: f64) -> f64 {
    v.max(lo).min(hi)
}

/// Distance from `p` to the segment `a`-`b`.
pub(crate) fn dist_to_segment(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let ab = b - a;
    let len_sq = ab.norm_sq();
    if len_sq <= 0.0 {
        return p.dist(a);
    }
    let t = clamp((p - a).dot(ab) / len_sq, 0.0, 1.0);
    p.dist(a + ab * t)
}

/// The angle in degrees, in `[0, 180]`, at `vertex` between the directions to `p1`
/// and to `p2` (0 if either point coincides with the vertex).
pub(crate) fn angle_at(vertex: Vec2, p1: Vec2, p2: Vec2) -> f64 {
    let a = p1 - vertex;
    let b = p2 - vertex;
    if a.norm_sq() == 0.0 || b.norm_sq() == 0.0 {
        return 0.0;
    }
    a.cross(b).abs().atan2(a.dot(b)).to_degrees()
}

/// The server's quantisation `Q(v, q) = rint(v / q) * q` (ties to even, like C's `rint`).
pub(crate) fn quantize(v: f64, q: f64) -> f64 {
    round_ties_even(v / q) * q
}

/// `x` rounded to the nearest integer, ties to even: the same value as
/// [`f64::round_ties_even`], bit for bit, without its library call on targets
/// with no rounding instruction (the x86-64 baseline). Below 2^52 in magnitude,
/// adding and subtracting 2^52 leaves exactly the integer that IEEE 754's
/// round-to-nearest-even picks; larger values, infinities and NaN are already
/// integral or stay as they are.
pub(crate) fn round_ties_even(x: f64) -> f64 {
    const TWO_52: f64 = 4_503_599_627_370_496.0;
    let a = x.abs();
    if a < TWO_52 {
        ((a + TWO_52) - TWO_52).copysign(x)
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalisation_range() {
        assert_eq!(normalize_deg(180.0), 180.0);
        assert_eq!(normalize_deg(-180.0), 180.0);
        assert!((normalize_deg(370.0) - 10.0).abs() < 1e-12);
        assert!((normalize_deg(-190.0) - 170.0).abs() < 1e-12);
        assert!(normalize_deg(f64::INFINITY).is_nan());
    }

    #[test]
    fn polar_and_dir_round_trip() {
        let v = Vec2::polar(2.0, 135.0);
        assert!((v.norm() - 2.0).abs() < 1e-12);
        assert!((v.dir() - 135.0).abs() < 1e-9);
        assert!((v.rotate(-45.0).dir() - 90.0).abs() < 1e-9);
    }

    #[test]
    fn segment_distance_and_angle() {
        let a = Vec2::new(0.0, 0.0);
        let b = Vec2::new(10.0, 0.0);
        assert!((dist_to_segment(Vec2::new(5.0, 3.0), a, b) - 3.0).abs() < 1e-12);
        assert!((dist_to_segment(Vec2::new(-4.0, 3.0), a, b) - 5.0).abs() < 1e-12);
        assert!((angle_at(a, b, Vec2::new(0.0, -1.0)) - 90.0).abs() < 1e-9);
    }

    #[test]
    fn quantisation_ties_to_even() {
        assert!((quantize(0.25, 0.1) - 0.2).abs() < 1e-12);
        assert!((quantize(1.26, 0.1) - 1.3).abs() < 1e-12);
    }

    #[test]
    fn rounding_matches_the_library_at_the_edges() {
        let edges = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            9.1e15,
            1e300,
            f64::MIN_POSITIVE,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for x in edges {
            assert_eq!(round_ties_even(x).to_bits(), x.round_ties_even().to_bits(), "{x}");
        }
        assert!(round_ties_even(f64::NAN).is_nan());
    }

    #[test]
    fn table_sines_are_the_computed_ones() {
        for deg in (-200..=200).map(f64::from).chain([-0.0, 0.5, -179.5, 1e10, f64::NAN]) {
            let (s, c) = sin_cos_deg(deg);
            let (ws, wc) = deg.to_radians().sin_cos();
            assert_eq!((s.to_bits(), c.to_bits()), (ws.to_bits(), wc.to_bits()), "{deg}");
        }
    }

    proptest::proptest! {
        /// The rounding is the library's, bit for bit, over every magnitude and
        /// at half-integers.
        #[test]
        fn rounding_is_the_librarys(bits in proptest::num::u64::ANY, half in -1e6..1e6f64) {
            let x = f64::from_bits(bits);
            if !x.is_nan() {
                proptest::prop_assert_eq!(round_ties_even(x).to_bits(), x.round_ties_even().to_bits());
            }
            let h = half.trunc() + 0.5;
            proptest::prop_assert_eq!(round_ties_even(h).to_bits(), h.round_ties_even().to_bits());
        }
    }
}
