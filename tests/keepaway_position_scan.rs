//! A measurement, not a check: the mean episode duration of every assignment of
//! the nine positioning points to the three keepers (9^3), the ball holder
//! following the threshold policy at two thresholds. Cited in
//! docs/results/RESULTS.md; run it with
//! `cargo test --release --test keepaway_position_scan -- --ignored --nocapture`.

use learnpnp::keepaway::episode::Keepaway;
use learnpnp::keepaway::features::PassLineDistances;
use learnpnp::keepaway::keeper::{KeeperAction, KeeperPolicy, SupportAction};
use learnpnp::keepaway::params::KeepawayConfig;
use learnpnp::keepaway::perception::PlayerView;
use learnpnp::keepaway::policies::{DEFAULT_HOLD_THRESHOLD, threshold_policy};
use learnpnp::keepaway::positions::PositioningPoint;

/// Threshold policy with the ball; a fixed point (or get-open) otherwise.
struct Static {
    points: Option<[PositioningPoint; 3]>,
    threshold: f64,
}

impl KeeperPolicy for Static {
    fn decide(&mut self, view: &PlayerView, _: &KeepawayConfig) -> KeeperAction {
        PassLineDistances::from_view(view).map_or(KeeperAction::Hold, |d| threshold_policy(&d, self.threshold))
    }
    fn support(&mut self, view: &PlayerView, cfg: &KeepawayConfig) -> SupportAction {
        match self.points {
            Some(p) => SupportAction::GoTo(p[view.me.index_in_team()].point(&cfg.region)),
            None => SupportAction::GetOpen,
        }
    }
}

#[test]
#[ignore]
fn scan_static_positions() {
    let cfg = KeepawayConfig::default();
    for threshold in [DEFAULT_HOLD_THRESHOLD, 5.0] {
        let mut game = Keepaway::new(cfg, 5).expect("valid config");
        let mut mean = |policy: &mut Static, episodes: usize| {
            (0..episodes).map(|_| game.run_episode(policy).seconds).sum::<f64>() / episodes as f64
        };
        let get_open = mean(
            &mut Static {
                points: None,
                threshold,
            },
            200,
        );
        let mut all = Vec::new();
        for i in 0..729 {
            let p = |k: usize| PositioningPoint::from_index(k).expect("index below 9");
            let points = [p(i % 9), p(i / 9 % 9), p(i / 81)];
            all.push((
                mean(
                    &mut Static {
                        points: Some(points),
                        threshold,
                    },
                    40,
                ),
                points,
            ));
        }
        all.sort_by(|a, b| b.0.total_cmp(&a.0));
        let average = all.iter().map(|a| a.0).sum::<f64>() / all.len() as f64;
        println!("threshold {threshold} m: get-open {get_open:.2} s; static assignments: mean {average:.2} s, best:");
        for (seconds, points) in all.iter().take(5) {
            println!("  {seconds:.2} s {points:?}");
        }
    }
}
