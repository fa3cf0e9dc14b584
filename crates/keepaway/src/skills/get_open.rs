//! Getting open for a pass (the framework's `getOpenForPassFromInRectangle`).

use super::fastest::{fastest_teammate, pass_origin};
use super::movement::{go_to_point, turn_body_to_point};
use crate::command::Command;
use crate::geometry::Vec2;
use crate::params::KeepawayConfig;
use crate::view::PlayerView;
use crate::world::NUM_PLAYERS;

/// Congestion at `p`: the sum of `1 / distance` to every other player (oneself
/// excluded; players exactly at `p` are skipped), summed in player order.
pub fn congestion(view: &PlayerView, p: Vec2) -> f64 {
    // Skipped players add +0.0, which leaves a sum of non-negative terms unchanged.
    inverse_distances(view, p).iter().fold(0.0, |c, x| c + x)
}

/// `1 / distance` from `p` to each player, 0 for oneself and for players exactly
/// at `p` (computed for all players at once, which the compiler vectorises).
fn inverse_distances(view: &PlayerView, p: Vec2) -> [f64; NUM_PLAYERS] {
    let me = view.me.index();
    let mut inv = [0.0; NUM_PLAYERS];
    for (k, (x, q)) in inv.iter_mut().zip(view.players.iter()).enumerate() {
        let d = q.pos.dist(p);
        *x = if k != me && d > 0.0 { 1.0 / d } else { 0.0 };
    }
    inv
}

/// Whether `obj` lies in the pass cone from `start` to `end` (the framework's
/// `getNrInSetInCone`): its projection on the line lies between the two ends, its
/// distance from the line is below `width x` the projection's distance from
/// `start`, and it is closer to `start` than `end` is.
pub fn in_cone(obj: Vec2, start: Vec2, end: Vec2, width: f64) -> bool {
    let line = end - start;
    let len_sq = line.norm_sq();
    if len_sq <= 0.0 {
        return false;
    }
    // Projection start + t * line: between the ends iff t in [0, 1].
    let t = (obj - start).dot(line) / len_sq;
    let proj = start + line * t;
    (0.0..=1.0).contains(&t) && proj.dist_sq(obj) < width * width * proj.dist_sq(start) && start.dist_sq(obj) < len_sq
}

/// The candidate points of the get-open grid: `grid x grid` points over the region
/// minus a `border` fraction on each side ({-7, -3.5, 0, 3.5, 7} on each axis for
/// the defaults), x-major order.
pub fn grid_points(cfg: &KeepawayConfig) -> impl Iterator<Item = Vec2> {
    let r = cfg.region;
    let s = cfg.skills;
    // Bounded as in `SkillParams::validate`, so that an unvalidated value cannot stall.
    let n = s.get_open_grid.clamp(2, 64);
    let mesh_x = r.length * (1.0 - 2.0 * s.get_open_border) / f64::from(n - 1);
    let mesh_y = r.width * (1.0 - 2.0 * s.get_open_border) / f64::from(n - 1);
    let x0 = -r.half_length() + s.get_open_border * r.length;
    let y0 = -r.half_width() + s.get_open_border * r.width;
    (0..n).flat_map(move |i| (0..n).map(move |j| Vec2::new(x0 + f64::from(i) * mesh_x, y0 + f64::from(j) * mesh_y)))
}

/// The least congested grid point with no opponent in the pass cone from
/// `pass_from`; the region's centre if every point is blocked.
pub fn least_congested_point(view: &PlayerView, cfg: &KeepawayConfig, pass_from: Vec2) -> Vec2 {
    let width = cfg.skills.pass_cone_width;
    let mut best = None;
    let mut best_c = f64::INFINITY;
    let mut points = grid_points(cfg).peekable();
    while points.peek().is_some() {
        let chunk = GridChunk::congestion(view, &mut points);
        for (&p, &c) in chunk.points[..chunk.len].iter().zip(&chunk.congestion) {
            if c < best_c && !view.opponents().any(|(_, o)| in_cone(o.pos, pass_from, p, width)) {
                best_c = c;
                best = Some(p);
            }
        }
    }
    best.unwrap_or(cfg.region.centre())
}

/// Up to [`GridChunk::POINTS`] grid points with their [`congestion`], found
/// player by player for all the points at once (which the compiler
/// vectorises), each point's sum in player order as [`congestion`] adds it.
struct GridChunk {
    points: [Vec2; GridChunk::POINTS],
    congestion: [f64; GridChunk::POINTS],
    len: usize,
}

impl GridChunk {
    /// Points per chunk (the default grid's 25 in one).
    const POINTS: usize = 32;

    /// The next points of `points` and their congestion in `view`.
    fn congestion(view: &PlayerView, points: &mut impl Iterator<Item = Vec2>) -> Self {
        let mut chunk = GridChunk {
            points: [Vec2::ZERO; Self::POINTS],
            congestion: [0.0; Self::POINTS],
            len: 0,
        };
        for (slot, p) in chunk.points.iter_mut().zip(points) {
            *slot = p;
            chunk.len += 1;
        }
        let me = view.me.index();
        for (k, q) in view.players.iter().enumerate() {
            for (c, &p) in chunk.congestion.iter_mut().zip(&chunk.points) {
                let d = q.pos.dist(p);
                *c += if k != me && d > 0.0 { 1.0 / d } else { 0.0 };
            }
        }
        chunk
    }
}

/// Go to a supporting position `point`: within `get_open_buffer` (1.5 m) of it,
/// turn to face the ball; otherwise [`go_to_point`].
pub fn go_to_support_point(view: &PlayerView, cfg: &KeepawayConfig, point: Vec2) -> Command {
    if view.own().pos.dist(point) < cfg.skills.get_open_buffer {
        turn_body_to_point(view, cfg, view.ball.pos, 1)
    } else {
        go_to_point(view, cfg, point)
    }
}

/// Get open for a pass that will start from `pass_from`.
pub fn get_open_from(view: &PlayerView, cfg: &KeepawayConfig, pass_from: Vec2) -> Command {
    let p = least_congested_point(view, cfg, pass_from);
    go_to_support_point(view, cfg, p)
}

/// Get open: the pass is expected from where the teammate fastest to the ball will
/// get it (the framework's `keeperSupport`, see [`pass_origin`]).
pub fn get_open(view: &PlayerView, cfg: &KeepawayConfig) -> Command {
    get_open_from(view, cfg, pass_origin(view, fastest_teammate(view, cfg), cfg))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_grid() {
        let cfg = KeepawayConfig::default();
        let pts: Vec<Vec2> = grid_points(&cfg).collect();
        assert_eq!(pts.len(), 25);
        assert!(pts[0].dist(Vec2::new(-7.0, -7.0)) < 1e-9);
        assert!(pts[24].dist(Vec2::new(7.0, 7.0)) < 1e-9);
        assert!(pts[12].dist(Vec2::ZERO) < 1e-9);
    }

    /// The congestion found a chunk of points at a time is [`congestion`]'s,
    /// to the bit, over every keeper's view of 20 episodes and grids of every
    /// size up to 12 x 12 (several chunks, a last one partly filled).
    #[test]
    fn chunked_congestion_is_congestion() {
        use crate::episode::Keepaway;
        use crate::perception::perceive;
        use crate::policies::BaselinePolicy;
        use crate::view::PlayerId;

        let mut checked = 0;
        for seed in 0..20 {
            let mut cfg = KeepawayConfig::default();
            cfg.skills.get_open_grid = 2 + (seed % 11) as u32;
            let mut game = Keepaway::new(cfg, seed).expect("valid config");
            let mut policy = BaselinePolicy::random(seed);
            while game.step(&mut policy).is_none() {
                for id in PlayerId::KEEPERS {
                    let view = perceive(game.simulator().field(), id, &cfg);
                    let mut points = grid_points(&cfg).peekable();
                    let mut all = grid_points(&cfg);
                    while points.peek().is_some() {
                        let chunk = GridChunk::congestion(&view, &mut points);
                        for (&p, &c) in chunk.points[..chunk.len].iter().zip(&chunk.congestion) {
                            assert_eq!(Some(p), all.next());
                            assert_eq!(c.to_bits(), congestion(&view, p).to_bits());
                            checked += 1;
                        }
                    }
                    assert_eq!(all.next(), None);
                }
            }
        }
        assert!(checked > 100_000, "{checked} points");
    }

    #[test]
    fn cone() {
        let s = Vec2::ZERO;
        let e = Vec2::new(10.0, 0.0);
        assert!(in_cone(Vec2::new(5.0, 1.0), s, e, 0.3));
        assert!(!in_cone(Vec2::new(5.0, 2.0), s, e, 0.3));
        assert!(!in_cone(Vec2::new(-1.0, 0.1), s, e, 0.3));
        assert!(!in_cone(Vec2::new(11.0, 0.1), s, e, 0.3));
    }
}
