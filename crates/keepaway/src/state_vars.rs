//! The 13 state variables of the original keepaway benchmark (3 vs 2).

use super::geometry::{Vec2, angle_at};
use super::view::PlayerView;
use super::world::Side;
use serde::{Deserialize, Serialize};

/// The benchmark's state, from one keeper's view. K1 is the keeper closest to the
/// ball (normally the one with it), K2 and K3 the other keepers and T1, T2 the
/// takers, both sorted by distance to K1; C is the region's centre. Distances in
/// metres, angles in degrees.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StateVars {
    /// Global indices of K1, K2, K3.
    pub keepers: [usize; 3],
    /// Global indices of T1, T2.
    pub takers: [usize; 2],
    /// d(K1, C).
    pub(crate) d_k1_c: f64,
    /// d(K1, K2), d(K1, K3).
    pub(crate) d_k1_k: [f64; 2],
    /// d(K1, T1), d(K1, T2).
    pub(crate) d_k1_t: [f64; 2],
    /// d(K2, C), d(K3, C).
    pub(crate) d_k_c: [f64; 2],
    /// d(T1, C), d(T2, C).
    pub(crate) d_t_c: [f64; 2],
    /// min_j d(K2, Tj), min_j d(K3, Tj).
    pub(crate) min_d_k_t: [f64; 2],
    /// min_j ang(K2, K1, Tj), min_j ang(K3, K1, Tj): the smallest angle at K1
    /// between a teammate and a taker.
    pub(crate) min_ang_k_t: [f64; 2],
}

impl StateVars {
    /// The variables seen by a keeper; `None` for a taker's view.
    pub fn from_view(view: &PlayerView) -> Option<StateVars> {
        if view.side() != Side::Keepers {
            return None;
        }
        let c = Vec2::ZERO;
        let pos = |i: usize| view.players[i].pos;
        let ball = view.ball.pos;
        let mut keepers = [0usize, 1, 2];
        // K1: closest to the ball (ties to the lower index).
        keepers.sort_by(|&a, &b| pos(a).dist(ball).total_cmp(&pos(b).dist(ball)).then(a.cmp(&b)));
        let k1 = pos(keepers[0]);
        let mut rest = [keepers[1], keepers[2]];
        rest.sort_by(|&a, &b| pos(a).dist(k1).total_cmp(&pos(b).dist(k1)).then(a.cmp(&b)));
        keepers = [keepers[0], rest[0], rest[1]];
        let t0 = Side::Takers.indices().start;
        let mut takers = [t0, t0 + 1];
        takers.sort_by(|&a, &b| pos(a).dist(k1).total_cmp(&pos(b).dist(k1)).then(a.cmp(&b)));
        let min_over_takers = |f: &dyn Fn(Vec2) -> f64| takers.iter().map(|&t| f(pos(t))).fold(f64::INFINITY, f64::min);
        let k = [pos(rest[0]), pos(rest[1])];
        Some(StateVars {
            keepers,
            takers,
            d_k1_c: k1.dist(c),
            d_k1_k: [k1.dist(k[0]), k1.dist(k[1])],
            d_k1_t: [k1.dist(pos(takers[0])), k1.dist(pos(takers[1]))],
            d_k_c: [k[0].dist(c), k[1].dist(c)],
            d_t_c: [pos(takers[0]).dist(c), pos(takers[1]).dist(c)],
            min_d_k_t: [min_over_takers(&|t| k[0].dist(t)), min_over_takers(&|t| k[1].dist(t))],
            min_ang_k_t: [
                min_over_takers(&|t| angle_at(k1, k[0], t)),
                min_over_takers(&|t| angle_at(k1, k[1], t)),
            ],
        })
    }

    /// The 13 values in the benchmark's order: d(K1,C), d(K1,K2), d(K1,K3),
    /// d(K1,T1), d(K1,T2), d(K2,C), d(K3,C), d(T1,C), d(T2,C), min d(K2,T),
    /// min d(K3,T), min ang(K2,K1,T), min ang(K3,K1,T).
    pub fn to_array(&self) -> [f64; 13] {
        [
            self.d_k1_c,
            self.d_k1_k[0],
            self.d_k1_k[1],
            self.d_k1_t[0],
            self.d_k1_t[1],
            self.d_k_c[0],
            self.d_k_c[1],
            self.d_t_c[0],
            self.d_t_c[1],
            self.min_d_k_t[0],
            self.min_d_k_t[1],
            self.min_ang_k_t[0],
            self.min_ang_k_t[1],
        ]
    }
}
