//! Mean episode durations of the baseline policies (ignored by default; run with
//! `cargo test --release --test keepaway_baselines -- --ignored --nocapture`,
//! `EPISODES=n` to change the sample size). Seeds are `1000..1000 + n`.

use learnpnp::keepaway::policies::BaselinePolicy;
use learnpnp::keepaway::{EndReason, KeepawayConfig, VisionMode, run_episode};

fn episodes() -> u64 {
    std::env::var("EPISODES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300)
}

fn report(name: &str, cfg: &KeepawayConfig, make: &dyn Fn(u64) -> BaselinePolicy) {
    let n = episodes();
    let (mut sum, mut sum_sq, mut out) = (0.0, 0.0, 0);
    for i in 0..n {
        let mut policy = make(i);
        let o = run_episode(cfg, 1000 + i, &mut policy).expect("valid config");
        sum += o.seconds;
        sum_sq += o.seconds * o.seconds;
        out += u64::from(o.end == EndReason::Out);
    }
    let mean = sum / n as f64;
    let sd = (sum_sq / n as f64 - mean * mean).max(0.0).sqrt();
    println!(
        "{name:>24}: {mean:6.2} s  (sd {sd:5.2}, se {:4.2}, {out}/{n} out)",
        sd / (n as f64).sqrt()
    );
}

#[test]
#[ignore]
fn baseline_durations() {
    let full = KeepawayConfig::default();
    let quantised = KeepawayConfig {
        vision: VisionMode::Quantised,
        ..full
    };
    report("random", &full, &BaselinePolicy::random);
    report("always hold", &full, &|_| BaselinePolicy::AlwaysHold);
    report("hand-coded", &full, &|_| BaselinePolicy::HandCoded);
    report("threshold (default)", &full, &|_| BaselinePolicy::threshold());
    report("hand-coded, quantised", &quantised, &|_| BaselinePolicy::HandCoded);
    report("threshold, quantised", &quantised, &|_| BaselinePolicy::threshold());
}

#[test]
#[ignore]
fn threshold_sweep() {
    let cfg = KeepawayConfig::default();
    for threshold in [2.5, 2.75, 3.0, 3.085, 3.25, 3.5, 3.75, 4.0, 5.0] {
        report(&format!("threshold {threshold}"), &cfg, &move |_| {
            BaselinePolicy::Threshold { threshold }
        });
    }
}
