//! Mean episode durations of the fixed keeper policies (random, always hold, the
//! framework's hand-coded policy, the thesis's threshold policy), played by all
//! three keepers, in each vision mode: the framework players' perception (the
//! default), full state and quantised.
//!
//! ```sh
//! cargo run --release -p learnpnp-probes --example keepaway_baselines -- [EPISODES]
//! ```
//!
//! Episode `i` of every policy starts from seed `1000 + i` (1000 episodes by
//! default). A measurement program: it prints numbers and checks nothing.

use learnpnp_probes::args;

use std::process::ExitCode;

use anyhow::{Context, Result};
use learnpnp_keepaway::policies::BaselinePolicy;
use learnpnp_keepaway::{EndReason, KeepawayConfig, VisionMode, run_episode};

/// Plays `n` episodes with a policy made by `make` (from the episode index) and
/// prints the mean duration with its 95% confidence interval (normal
/// approximation), its standard deviation, the longest episode, and how many
/// episodes ended with the ball out of the region.
fn report(name: &str, cfg: &KeepawayConfig, n: u64, make: &dyn Fn(u64) -> BaselinePolicy) -> Result<()> {
    let (mut sum, mut sum_sq, mut out, mut longest) = (0.0, 0.0, 0u64, 0.0f64);
    for i in 0..n {
        let mut policy = make(i);
        let o = run_episode(cfg, 1000 + i, &mut policy).context("running an episode")?;
        sum += o.seconds;
        sum_sq += o.seconds * o.seconds;
        out += u64::from(o.end == EndReason::Out);
        longest = longest.max(o.seconds);
    }
    let count = n as f64;
    let mean = sum / count;
    let sd = (sum_sq / count - mean * mean).max(0.0).sqrt();
    let half = 1.96 * sd / count.sqrt();
    println!(
        "{name:>28}: {mean:6.2} s  [{:6.2}, {:6.2}]  (sd {sd:5.2}, longest {longest:6.1} s, {out}/{n} out)",
        mean - half,
        mean + half
    );
    Ok(())
}

fn run() -> Result<()> {
    let n = args::positive_count("EPISODES", 1000, "keepaway_baselines [EPISODES]")?;
    let framework = KeepawayConfig::default();
    let with = |vision| KeepawayConfig { vision, ..framework };
    let (full, quantised) = (with(VisionMode::FullState), with(VisionMode::Quantised));
    for (vision, cfg) in [
        ("framework", &framework),
        ("full state", &full),
        ("quantised", &quantised),
    ] {
        println!("{vision}, {n} episodes per policy:");
        report("random", cfg, n, &BaselinePolicy::random)?;
        report("always hold", cfg, n, &|_| BaselinePolicy::AlwaysHold)?;
        report("hand-coded", cfg, n, &|_| BaselinePolicy::HandCoded)?;
        report("threshold", cfg, n, &|_| BaselinePolicy::threshold())?;
    }
    Ok(())
}

fn main() -> ExitCode {
    args::exit_code(run())
}
