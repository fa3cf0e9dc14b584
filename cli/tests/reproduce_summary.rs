//! What `reproduce` and `experiment` report: the same baseline gives the same
//! numbers and the same bar through both; summary.md gives units, the
//! thesis's claim beside each figure, and says when a greedy score does not apply.

use crate::util::run_quietly;
use learnpnp::experiment::options::DomainName;
use learnpnp::experiment::output::{greedy_text, summary};
use learnpnp::experiment::presets;
use learnpnp::experiment::report::summary_markdown;
use learnpnp_cli::args::parse_experiment_flags;

#[test]
fn a_baseline_is_the_same_through_reproduce_and_experiment() {
    let figure = presets::figure("7.baselines").expect("the baselines preset");
    let preset = figure
        .curves
        .iter()
        .find(|c| c.label == "hand-coded")
        .expect("the hand-coded curve")
        .clone();
    let mut experiment = parse_experiment_flags(&["--policy", "handcoded"])
        .expect("valid flags")
        .spec(DomainName::KeepawayFixed)
        .expect("a spec");
    // Everything but the label.
    assert_eq!(experiment.domain, preset.domain);
    assert_eq!(experiment.learner, preset.learner);
    assert_eq!(experiment.protocol, preset.protocol);
    assert_eq!(experiment.seed, preset.seed);
    // So the same (shortened) run gives the same numbers.
    let mut short = preset.clone();
    for spec in [&mut short, &mut experiment] {
        spec.protocol.runs = 2;
        spec.protocol.episodes = 5;
        spec.protocol.eval_every = 5;
        spec.protocol.eval_episodes = 4;
    }
    let a = summary(&run_quietly(&short, 1));
    let b = summary(&run_quietly(&experiment, 2));
    assert_eq!(a.final_mean, b.final_mean);
    assert_eq!(a.final_ci95, b.final_ci95);
    assert_eq!(a.final_greedy_mean, None, "a fixed policy has no greedy score");
    assert_eq!(greedy_text(&a), "n/a: a fixed policy learns nothing");
}

#[test]
fn the_summary_table_has_units_claims_and_references() {
    let mut pr = presets::figure("6.3").expect("a preset");
    pr.curves.truncate(1);
    let mut kp = presets::figure("7.baselines").expect("a preset");
    kp.curves.truncate(1);
    let mut runs = Vec::new();
    for figure in [&mut pr, &mut kp] {
        let spec = &mut figure.curves[0];
        spec.protocol.runs = 2;
        spec.protocol.episodes = 4;
        spec.protocol.eval_every = 2;
        spec.protocol.eval_episodes = 2;
        runs.push(vec![summary(&run_quietly(spec, 1))]);
    }
    let md = summary_markdown(&[(&pr, &runs[0]), (&kp, &runs[1])]);
    assert!(md.contains(&format!("## Figure 6.3: {}", pr.title)), "{md}");
    assert!(md.contains(&format!("Thesis: {}", pr.claim)), "{md}");
    assert!(md.contains("Reference: best memoryless policy, exact: 0.263"), "{md}");
    assert!(md.contains(&format!("Thesis: {}", kp.claim)), "{md}");
    // Keepaway scores in seconds, its greedy score not applicable.
    let row = md
        .lines()
        .find(|l| l.starts_with("| random |"))
        .expect("the random policy's row");
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    assert!(
        cells[2].ends_with(" s") && cells[3].contains(" s .. ") && cells[3].ends_with(" s"),
        "{row}"
    );
    assert_eq!(cells[4], "n/a: a fixed policy learns nothing", "{row}");
    let grid_row = md
        .lines()
        .find(|l| l.starts_with("| Sarsa(0.9) e-greedy |"))
        .expect("a row");
    let cells: Vec<&str> = grid_row.split('|').map(str::trim).collect();
    assert!(
        !cells[2].ends_with(" s") && !cells[3].contains(" s"),
        "a return has no unit: {grid_row}"
    );
    cells[4].parse::<f64>().expect("a measured greedy score");
    assert!(cells[6].ends_with(" s"), "the wall time is in seconds: {grid_row}");
}
