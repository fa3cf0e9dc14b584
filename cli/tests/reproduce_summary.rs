//! What `reproduce` and `experiment` report: the same baseline gives the same
//! numbers and the same bar through both; summary.md gives units, the
//! thesis's claim beside each figure, and says when a greedy score does not
//! apply; the summary lines say when there is no interval or no score.

use crate::learnpnp;
use crate::util::{run_quietly, temp_dir, text};
use learnpnp::experiment::options::DomainName;
use learnpnp::experiment::output::{greedy_text, summary};
use learnpnp::experiment::presets;
use learnpnp::experiment::report::summary_markdown;
use learnpnp_flags::args::parse_experiment_flags;

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

/// The standard output of `learnpnp` with `args`, which must succeed.
fn reported(args: &[&str]) -> String {
    let o = learnpnp(args);
    assert!(o.status.success(), "{args:?}: {}", text(&o.stderr));
    text(&o.stdout)
}

#[test]
fn summary_lines_say_when_there_is_no_interval_or_no_score() {
    let dir = temp_dir("summary-lines");
    let experiment = |name: &str, flags: &[&str]| {
        let out = dir.join(name).display().to_string();
        let mut args = vec![
            "experiment",
            "parr-russell",
            "--algo",
            "eps-sosmc",
            "--episodes",
            "20",
            "--eval-every",
            "10",
            "--out",
            &out,
        ];
        args.extend_from_slice(flags);
        let stdout = reported(&args);
        let line = stdout
            .lines()
            .find(|l| l.starts_with("eps-sosmc on parr-russell: "))
            .unwrap_or_else(|| panic!("no summary line: {stdout}"))
            .to_string();
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join(name).join("summary.json")).unwrap()).unwrap();
        (line, summary)
    };
    // Two runs: the mean and its interval.
    let (line, _) = experiment("two", &["--runs", "2"]);
    assert!(
        line.contains(": final evaluation ") && line.contains(" (95% CI "),
        "{line}"
    );
    // One run: the mean, and no interval of zero width.
    let (line, _) = experiment("one", &["--runs", "1"]);
    assert!(
        line.contains(": final evaluation ") && line.contains(" (one run: no interval), greedy "),
        "{line}"
    );
    assert!(!line.contains("95% CI"), "{line}");
    // No evaluation episodes: no score, where the runs recorded 0.
    let (line, summary) = experiment("none", &["--runs", "2", "--eval-episodes", "0"]);
    assert!(
        line.starts_with("eps-sosmc on parr-russell: no evaluation episodes, greedy "),
        "{line}"
    );
    assert!(!line.contains("95% CI") && !line.contains("final evaluation"), "{line}");
    // summary.json keeps its numbers.
    assert_eq!(summary["final_mean"], 0.0);
    assert_eq!(summary["final_ci95"], serde_json::json!([0.0, 0.0]));

    // A figure of one run (4.3): its line and its row of summary.md.
    let out = dir.join("reproduced");
    let stdout = reported(&["reproduce", "4.3", "--out", out.to_str().unwrap()]);
    let line = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("e-SoSMC "))
        .unwrap_or_else(|| panic!("no summary line: {stdout}"));
    assert!(
        line.contains(" final evaluation ") && line.contains(" (one run: no interval) "),
        "{line}"
    );
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    let row = md
        .lines()
        .find(|l| l.starts_with("| e-SoSMC |"))
        .expect("the curve's row");
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    cells[2].parse::<f64>().expect("a mean");
    assert_eq!(cells[3], "one run: no interval", "{row}");
    let _ = std::fs::remove_dir_all(&dir);
}
