//! How long the framework's hand-coded keepers keep the ball, by the players'
//! visual phases, with the server in real time (the framework's
//! synchronisation) and in synchronous mode.
//!
//! ```sh
//! cargo run --release -p learnpnp-probes --example keepaway_see_phases -- [RUNS]
//! ```
//!
//! Run `i` is one episode from seed `1000 + i` (2000 runs by default), with
//! the framework players' perception; each run's phases are those its
//! players' connections and synchronisation give. A player is late when one
//! of its sees comes after it has acted. Runs are grouped by how many keepers
//! and takers are late, then by the keepers' and the takers' phases (sorted). A measurement program: it prints
//! numbers and checks nothing.

use learnpnp_probes::args;

use std::collections::BTreeMap;
use std::process::ExitCode;

use anyhow::{Context, Result};
use learnpnp::named::Named;
use learnpnp_keepaway::policies::BaselinePolicy;
use learnpnp_keepaway::timing::{SeeArrival, SeePhase, see_arrival};
use learnpnp_keepaway::world::NUM_KEEPERS;
use learnpnp_keepaway::{KeepawayConfig, Perception, ServerTimer, run_episode};

/// Whether a player with `phase` sees after acting in some step.
fn late(phase: SeePhase, timer: ServerTimer) -> bool {
    (0..3).any(|c| see_arrival(phase, c, timer) == SeeArrival::AfterDecision)
}

/// Mean, 95% half-width (normal approximation) and count of `xs`.
fn summary(xs: &[f64]) -> (f64, f64, usize) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, 1.96 * (var / n).sqrt(), xs.len())
}

fn print_row(label: &str, xs: &[f64]) {
    let (mean, half, n) = summary(xs);
    println!(
        "{label:>44}: {mean:6.2} s  [{:6.2}, {:6.2}]  ({n} runs)",
        mean - half,
        mean + half
    );
}

fn run() -> Result<()> {
    let runs = args::positive_count("RUNS", 2000, "keepaway_see_phases [RUNS]")?;
    for timer in [ServerTimer::RealTime, ServerTimer::Synchronous] {
        let cfg = KeepawayConfig {
            timer,
            ..KeepawayConfig::default()
        };
        let (mut all, mut by_late, mut by_phases) = (Vec::new(), BTreeMap::new(), BTreeMap::new());
        for i in 0..runs {
            let seed = 1000 + i;
            let phases = Perception::new(&cfg, seed).phases();
            let o = run_episode(&cfg, seed, &mut BaselinePolicy::HandCoded).context("running an episode")?;
            let (keepers, takers) = phases.split_at(NUM_KEEPERS);
            let count = |ps: &[SeePhase]| ps.iter().filter(|&&p| late(p, timer)).count();
            by_late
                .entry((count(keepers), count(takers)))
                .or_insert_with(Vec::new)
                .push(o.seconds);
            let sorted = |ps: &[SeePhase]| {
                let mut v: Vec<usize> = ps
                    .iter()
                    .map(|&p| SeePhase::ALL.iter().position(|&q| q == p).unwrap_or(0))
                    .collect();
                v.sort_unstable();
                v
            };
            by_phases
                .entry((sorted(keepers), sorted(takers)))
                .or_insert_with(Vec::new)
                .push(o.seconds);
            all.push(o.seconds);
        }
        println!(
            "{} server, hand-coded keepers, {runs} single-episode runs:",
            timer.name()
        );
        print_row("all runs", &all);
        for ((k, t), xs) in &by_late {
            print_row(&format!("{k} late keepers, {t} late takers"), xs);
        }
        for ((keepers, takers), xs) in &by_phases {
            print_row(&format!("phases: keepers {keepers:?}, takers {takers:?}"), xs);
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    args::exit_code(run())
}
