//! Experiments and reproductions sharded across machines (`--shard I/N`)
//! and merged (`learnpnp merge`): the merged result is what one machine
//! writes, file for file (the wall-clock times aside, which the merge sums),
//! and a merge that cannot be right is refused with the reason.

use std::path::Path;

use crate::learnpnp;
use crate::util::{temp_dir, text};
use learnpnp::experiment::output::write_shard_results;
use learnpnp::experiment::result_dir::ResultDir;
use learnpnp::experiment::runner::{ExperimentOutput, RunOptions, run_experiment};
use learnpnp::experiment::shard::{Shard, ShardRecord, merge};

const EXPERIMENT: [&str; 10] = [
    "experiment",
    "parr-russell",
    "--algo",
    "sarsa-lambda",
    "--runs",
    "5",
    "--episodes",
    "200",
    "--seed",
    "9",
];

fn ok(args: &[&str]) {
    let output = learnpnp(args);
    assert!(output.status.success(), "{args:?}: {}", text(&output.stderr));
}

fn refused(args: &[&str]) -> String {
    let output = learnpnp(args);
    assert!(!output.status.success(), "{args:?} was not refused");
    text(&output.stderr)
}

/// A summary without its wall-clock figures.
fn numbers_of(summary: &Path) -> String {
    std::fs::read_to_string(summary)
        .unwrap()
        .lines()
        .filter(|l| !l.contains("wall_seconds") && !l.contains("per_second"))
        .collect::<Vec<_>>()
        .join("\n")
}

fn assert_same(a: &Path, b: &Path, files: &[&str]) {
    for file in files {
        assert_eq!(
            std::fs::read(a.join(file)).unwrap(),
            std::fs::read(b.join(file)).unwrap(),
            "{file} differs"
        );
    }
}

#[test]
fn shards_merged_are_the_experiment_one_machine_runs() {
    let dir = temp_dir("shards-experiment");
    let path = |name: &str| dir.join(name).display().to_string();
    ok(&[&EXPERIMENT[..], &["--out", &path("whole"), "--threads", "2"]].concat());
    for i in 0..3 {
        let shard = format!("{i}/3");
        ok(&[&EXPERIMENT[..], &["--out", &path(&format!("s{i}")), "--shard", &shard]].concat());
    }
    ok(&["merge", &path("merged"), &path("s2"), &path("s0"), &path("s1")]);
    let files = [
        "curve.csv",
        "runs.csv",
        "episodes.csv",
        "traces.csv",
        "values.bin",
        "curve.svg",
    ];
    assert_same(&dir.join("whole"), &dir.join("merged"), &files);
    assert_eq!(
        numbers_of(&dir.join("whole/summary.json")),
        numbers_of(&dir.join("merged/summary.json"))
    );

    // Refused, saying why.
    let missing = refused(&["merge", &path("m1"), &path("s0"), &path("s1")]);
    assert!(missing.contains("shard(s) 2 of 3 missing"), "{missing}");
    let twice = refused(&["merge", &path("m2"), &path("s0"), &path("s0"), &path("s1"), &path("s2")]);
    assert!(twice.contains("shard 0/3 is given twice"), "{twice}");
    let mut other = EXPERIMENT.to_vec();
    other[9] = "10";
    ok(&[&other[..], &["--out", &path("t1"), "--shard", "1/3"]].concat());
    let foreign = refused(&["merge", &path("m3"), &path("s0"), &path("t1"), &path("s2")]);
    assert!(foreign.contains("shards of different experiments"), "{foreign}");
    let whole = refused(&["merge", &path("m4"), &path("whole"), &path("s1")]);
    assert!(whole.contains("neither an experiment's shard"), "{whole}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_partial_shard_is_refused_with_the_runs_it_lacks() {
    let dir = temp_dir("shards-partial");
    let spec = learnpnp_flags::args::parse_experiment_flags(&EXPERIMENT[2..])
        .unwrap()
        .spec(learnpnp::experiment::options::DomainName::ParrRussell)
        .unwrap();
    let mut written = Vec::new();
    for index in 0..2 {
        let shard = Shard { index, count: 2 };
        let runs = shard.runs(spec.protocol.runs);
        // Shard 1 stopped after its first run: a partial shard.
        let played = if index == 1 { &runs[..1] } else { &runs[..] };
        let options = RunOptions {
            threads: 1,
            progress: false,
            stop: None,
            only: Some(played),
            feed: None,
        };
        let output: ExperimentOutput = run_experiment(&spec, options, Default::default()).unwrap();
        let path = dir.join(format!("s{index}"));
        let record = ShardRecord { shard, runs };
        write_shard_results(&output, Some(&record), &mut ResultDir::open(&path).unwrap()).unwrap();
        written.push(path);
    }
    let error = merge(&written).unwrap_err().to_string();
    assert!(error.contains("shard 1/2 is partial: run(s) 3 missing"), "{error}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_sharded_reproduction_merges_into_the_figures_one_machine_draws() {
    let dir = temp_dir("shards-reproduce");
    let path = |name: &str| dir.join(name).display().to_string();
    ok(&["reproduce", "4.3", "--runs", "3", "--out", &path("whole")]);
    for i in 0..2 {
        let shard = format!("{i}/2");
        ok(&[
            "reproduce",
            "4.3",
            "--runs",
            "3",
            "--out",
            &path(&format!("r{i}")),
            "--shard",
            &shard,
        ]);
    }
    ok(&["merge", &path("merged"), &path("r1"), &path("r0")]);
    let curve = "fig4.3/e-sosmc";
    assert_same(
        &dir.join("whole").join(curve),
        &dir.join("merged").join(curve),
        &["curve.csv", "runs.csv", "episodes.csv", "traces.csv", "values.bin"],
    );
    let table = |p: &str| {
        std::fs::read_to_string(dir.join(p).join("summary.md"))
            .unwrap()
            .lines()
            .map(|l| l.rsplit_once("| ").map_or(l, |(row, _)| row).to_string())
            .collect::<Vec<_>>()
    };
    assert_eq!(
        table("whole"),
        table("merged"),
        "summary.md, the wall-time column aside"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
