//! The mean episode duration of every assignment of the nine positioning points
//! (thesis Figure 7.4) to the three keepers (9^3 = 729), the ball holder
//! following the threshold policy at its one distance
//! ([`DEFAULT_HOLD_THRESHOLD`]), against the framework's get-open supporters.
//!
//! ```sh
//! cargo run --release -p learnpnp-probes --example keepaway_position_scan -- [EPISODES]
//! ```
//!
//! Every assignment plays the same seeds `0..EPISODES` (40 by default; get-open
//! plays five times as many). A measurement program: it prints numbers and
//! checks nothing.

use learnpnp_probes::args;

use std::process::ExitCode;

use anyhow::{Context, Result};
use learnpnp_keepaway::features::{DEFAULT_HOLD_THRESHOLD, PassLineDistances};
use learnpnp_keepaway::keeper::{KeeperAction, KeeperPolicy, SupportAction};
use learnpnp_keepaway::params::KeepawayConfig;
use learnpnp_keepaway::policies::threshold_policy;
use learnpnp_keepaway::positions::PositioningPoint;
use learnpnp_keepaway::run_episode;
use learnpnp_keepaway::view::PlayerView;

/// The threshold policy with the ball; a fixed point per keeper (or get-open) otherwise.
struct Static {
    points: Option<[PositioningPoint; 3]>,
}

impl KeeperPolicy for Static {
    fn decide(&mut self, view: &PlayerView, _: &KeepawayConfig) -> KeeperAction {
        PassLineDistances::from_view(view).map_or(KeeperAction::Hold, |d| threshold_policy(&d, DEFAULT_HOLD_THRESHOLD))
    }
    fn support(&mut self, view: &PlayerView, cfg: &KeepawayConfig) -> SupportAction {
        match self.points {
            Some(p) => SupportAction::GoTo(p[view.me.index_in_team()].point(&cfg.region)),
            None => SupportAction::GetOpen,
        }
    }
}

/// Mean duration (s) over seeds `0..episodes`.
fn mean(cfg: &KeepawayConfig, points: Option<[PositioningPoint; 3]>, episodes: u64) -> Result<f64> {
    let mut total = 0.0;
    for seed in 0..episodes {
        total += run_episode(cfg, seed, &mut Static { points })
            .context("running an episode")?
            .seconds;
    }
    Ok(total / episodes as f64)
}

/// The assignment with index `i` in `0..729` (keeper 1 varies fastest).
fn assignment(i: usize) -> [PositioningPoint; 3] {
    let p = |k: usize| PositioningPoint::ALL[k % 9];
    [p(i), p(i / 9), p(i / 81)]
}

fn run() -> Result<()> {
    let episodes = args::positive_count("EPISODES", 40, "keepaway_position_scan [EPISODES]")?;
    let cfg = KeepawayConfig::default();
    let get_open = mean(&cfg, None, 5 * episodes)?;
    // Two workers, each taking every other assignment.
    let results: Vec<(f64, [PositioningPoint; 3])> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..2)
            .map(|w| {
                s.spawn(move || {
                    (w..729)
                        .step_by(2)
                        .map(|i| mean(&cfg, Some(assignment(i)), episodes).map(|m| (m, assignment(i))))
                        .collect::<Result<Vec<_>>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|h| h.join().map_err(|_| anyhow::anyhow!("a worker panicked"))?)
            .collect::<Result<Vec<_>>>()
            .map(|v| v.into_iter().flatten().collect())
    })?;
    let mut all = results;
    all.sort_by(|a, b| {
        b.0.total_cmp(&a.0)
            .then_with(|| format!("{:?}", a.1).cmp(&format!("{:?}", b.1)))
    });
    let average = all.iter().map(|a| a.0).sum::<f64>() / all.len() as f64;
    println!(
        "threshold {DEFAULT_HOLD_THRESHOLD} m: get-open {get_open:.2} s ({} episodes); \
         static assignments ({episodes} episodes each): mean {average:.2} s, best:",
        5 * episodes
    );
    for (seconds, points) in all.iter().take(5) {
        println!("  {seconds:.2} s {points:?}");
    }
    use PositioningPoint::{Corner2, Corner3, Middle1};
    let thesis = |p: &[PositioningPoint; 3]| {
        let mut s = *p;
        s.sort_by_key(|q| q.index());
        let mut t = [Corner2, Corner3, Middle1];
        t.sort_by_key(|q| q.index());
        s == t
    };
    if let Some((rank, (seconds, points))) = all.iter().enumerate().find(|(_, (_, p))| thesis(p)) {
        println!(
            "best with the thesis's Figure 7.6 set {{middle 1, corner 2, corner 3}}: rank {} of 729, {seconds:.2} s {points:?}",
            rank + 1
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    args::exit_code(run())
}
