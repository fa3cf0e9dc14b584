//! Interrupted experiments keep their completed runs, and resuming them gives
//! the numbers of an uninterrupted experiment, bit for bit.

use crate::util::temp_dir;
use std::path::Path;
use std::sync::atomic::AtomicBool;

use learnpnp::experiment::checkpoint::{CHECKPOINT, ResumePoint, resume_point};
use learnpnp::experiment::options::DomainName;
use learnpnp::experiment::output::write_results;
use learnpnp::experiment::presets;
use learnpnp::experiment::result_dir::{Contents, ResultDir};
use learnpnp::experiment::runner::{Completed, ExperimentOutput, RunOptions, run_experiment};
use learnpnp::experiment::spec::ExperimentSpec;

fn spec(args: &[&str]) -> ExperimentSpec {
    learnpnp_flags::args::parse_experiment_flags(args)
        .expect("valid flags")
        .spec(DomainName::ParrRussell)
        .expect("a valid spec")
}

fn run(spec: &ExperimentSpec, threads: usize, stop: Option<&AtomicBool>, completed: Completed) -> ExperimentOutput {
    let options = RunOptions {
        threads,
        progress: false,
        stop,
        only: None,
        feed: None,
    };
    run_experiment(spec, options, completed).expect("the experiment runs")
}

/// The files that carry the numbers (the summary's timings aside).
const NUMBERS: [&str; 5] = ["curve.csv", "runs.csv", "episodes.csv", "traces.csv", "values.bin"];

fn assert_same_files(a: &Path, b: &Path) {
    for file in NUMBERS {
        assert_eq!(
            std::fs::read(a.join(file)).expect("present"),
            std::fs::read(b.join(file)).expect("present"),
            "{file} differs"
        );
    }
    let figures = |dir: &Path| {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).expect("summary")).expect("json");
        (
            v["final_mean"].clone(),
            v["final_ci95"].clone(),
            v["final_greedy_mean"].clone(),
            v["total_episodes"].clone(),
            v["complete"].clone(),
            v["spec"].clone(),
        )
    };
    assert_eq!(figures(a), figures(b));
}

#[test]
fn a_resumed_experiment_ends_with_the_numbers_of_an_uninterrupted_one() {
    let dir = temp_dir("lib");
    // Six runs of 150 episodes, seeded: this one and another that differs only in its seed.
    let seeded = |seed: &str| {
        self::spec(&[
            "--algo",
            "eps-sosmc",
            "--runs",
            "6",
            "--episodes",
            "150",
            "--eval-every",
            "50",
            "--seed",
            seed,
        ])
    };
    let spec = seeded("11");
    let whole = run(&spec, 2, None, Completed::default());
    assert!(whole.is_complete());
    let mut reference = ResultDir::open(dir.join("reference")).expect("usable");
    write_results(&whole, &mut reference).expect("written");

    // Interrupted with runs 0, 2 and 5 done (any subset may finish first with
    // several threads): a partial result that says so.
    let kept: Vec<_> = whole
        .runs
        .iter()
        .filter(|r| [0, 2, 5].contains(&r.run))
        .cloned()
        .collect();
    let partial = ExperimentOutput {
        runs: kept,
        ..whole.clone()
    };
    assert!(!partial.is_complete());
    let mut out = ResultDir::open(dir.join("out")).expect("usable");
    let summary = write_results(&partial, &mut out).expect("written");
    assert!(!summary.complete);
    assert_eq!(summary.runs_completed, 3);
    let Contents::Results(manifest) = out.contents().expect("readable") else {
        panic!("a result set")
    };
    assert!(!manifest.complete && manifest.files.iter().any(|f| f == CHECKPOINT));
    assert_eq!((manifest.runs_completed, manifest.runs_planned), (3, 6));

    // Read back and continued, on another thread count: the same files.
    let ResumePoint::Partial(completed) = resume_point(&out, &spec).expect("resumable") else {
        panic!("a partial result")
    };
    assert_eq!(completed.runs.len(), 3);
    let resumed = run(&spec, 1, None, completed);
    assert!(resumed.is_complete());
    write_results(&resumed, &mut out).expect("written");
    assert_same_files(&dir.join("reference"), &dir.join("out"));
    assert!(
        !dir.join("out").join(CHECKPOINT).exists(),
        "a complete result keeps no checkpoint"
    );
    assert!(matches!(resume_point(&out, &spec), Ok(ResumePoint::Complete)));

    // Another experiment does not resume from these results.
    let other = seeded("12");
    let err = resume_point(&out, &other).expect_err("another seed");
    assert!(err.to_string().contains("another experiment"), "{err}");
    write_results(&partial, &mut out).expect("written");
    let err = resume_point(&out, &other).expect_err("another seed");
    assert!(err.to_string().contains("another experiment"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_stopped_experiment_returns_only_whole_runs_identical_to_the_uninterrupted_ones() {
    let spec = spec(&[
        "--algo",
        "sarsa-lambda",
        "--runs",
        "8",
        "--episodes",
        "400",
        "--eval-every",
        "100",
    ]);
    let whole = run(&spec, 2, None, Completed::default());
    // Stopped before it starts: nothing runs.
    let stop = AtomicBool::new(true);
    assert!(run(&spec, 2, Some(&stop), Completed::default()).runs.is_empty());
    // Stopped from another thread while it runs: whatever completed is whole.
    let stop = AtomicBool::new(false);
    let stopped = std::thread::scope(|s| {
        s.spawn(|| {
            std::thread::sleep(std::time::Duration::from_millis(30));
            stop.store(true, std::sync::atomic::Ordering::Relaxed);
        });
        run(&spec, 2, Some(&stop), Completed::default())
    });
    for r in &stopped.runs {
        assert_eq!(Some(r), whole.runs.iter().find(|w| w.run == r.run), "run {}", r.run);
    }
    // Resumed from there, the experiment is the uninterrupted one.
    let completed = Completed {
        runs: stopped.runs.clone(),
        wall_seconds: stopped.wall_seconds,
    };
    let resumed = run(&spec, 2, None, completed);
    assert_eq!(resumed.runs, whole.runs);
    assert!(resumed.wall_seconds >= stopped.wall_seconds);
}

#[test]
fn completed_runs_that_do_not_fit_the_spec_are_refused() {
    let spec = spec(&[
        "--algo",
        "eps-sosmc",
        "--runs",
        "2",
        "--episodes",
        "20",
        "--eval-every",
        "10",
    ]);
    let whole = run(&spec, 1, None, Completed::default());
    let twice = Completed {
        runs: vec![whole.runs[0].clone(), whole.runs[0].clone()],
        wall_seconds: 0.0,
    };
    let err = run_experiment(&spec, RunOptions::default(), twice).expect_err("repeated run");
    assert!(err.to_string().contains("repeated"), "{err}");
}

#[test]
fn specs_read_from_json_are_validated() {
    // Every preset survives JSON (negative infinity included) and validates.
    for figure in presets::figures() {
        for spec in figure.curves {
            let text = serde_json::to_string(&spec).expect("json");
            assert_eq!(ExperimentSpec::from_json(&text).expect("valid"), spec, "{}", spec.label);
        }
    }
    let spec = spec(&["--algo", "sarsa-lambda"]);
    let mut json: serde_json::Value = serde_json::to_value(&spec).expect("json");
    json["learner"]["alpha"] = serde_json::json!(5.0);
    let err = ExperimentSpec::from_json(&json.to_string()).expect_err("alpha out of range");
    assert!(err.to_string().contains("alpha: 5 is out of range"), "{err}");
    json["learner"]["alpha"] = serde_json::json!(0.1);
    json["protocol"]["eval_every"] = serde_json::json!(1_000_000);
    let err = ExperimentSpec::from_json(&json.to_string()).expect_err("eval-every beyond the run");
    assert!(err.to_string().contains("eval-every"), "{err}");
    json["protocol"]["eval_every"] = serde_json::json!(20);
    json["algorithm"] = serde_json::json!("eps-sosmc");
    let err = ExperimentSpec::from_json(&json.to_string()).expect_err("TD parameters for SoSMC");
    assert!(err.to_string().contains("not those of eps-sosmc"), "{err}");
    assert!(ExperimentSpec::from_json("{").is_err());
}
