//! Result directories through the binary: one writer per directory, checked
//! before any work, and never a mix of two runs whatever is killed when.

use crate::util::{temp_dir, text, write_in};
use crate::{learnpnp, short_experiment};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use learnpnp::experiment::result_dir::{Contents, ResultDir};

fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_learnpnp"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs")
}

/// A short Parr-Russell experiment with this seed into `out`.
fn experiment_args(out: &Path, seed: u64, episodes: u64) -> Vec<String> {
    let (episodes, seed) = (episodes.to_string(), seed.to_string());
    let mut args = short_experiment("parr-russell", "eps-sosmc", "4", &episodes);
    let out = out.to_str().expect("utf-8 path");
    args.extend(["--eval-every", "50", "--threads", "1", "--seed", &seed, "--out", out]);
    args.into_iter().map(String::from).collect()
}

fn as_strs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

/// Polls until `path` exists (the other process holds its lock).
fn wait_for(path: &Path) {
    let start = Instant::now();
    while !path.exists() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "{} never appeared",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Visible entries of `dir`, sorted.
fn visible(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("listable")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    names.sort();
    names
}

#[test]
fn a_second_experiment_on_the_same_directory_is_refused_at_once() {
    let dir = temp_dir("concurrent");
    let out = dir.join("run");
    // A long experiment holds the directory...
    let mut first = spawn(&as_strs(&experiment_args(&out, 1, 10_000_000)));
    wait_for(&dir.join(".run.lock"));
    // ...so a second one is refused before it computes anything.
    let second = learnpnp(&as_strs(&experiment_args(&out, 2, 200)));
    assert_eq!(second.status.code(), Some(2), "{}", text(&second.stderr));
    let err = text(&second.stderr);
    assert!(err.contains("another process") && err.contains("run"), "{err}");
    assert!(!text(&second.stdout).contains("final evaluation"), "no result reported");
    // Killed before it finished, the first leaves no result, only hidden
    // staging that the next user of the directory removes.
    first.kill().expect("kill");
    first.wait().expect("wait");
    assert!(!out.exists(), "no result was published");
    let opened = ResultDir::open(&out).expect("the lock died with its holder");
    assert_eq!(opened.contents().expect("readable"), Contents::Empty);
    drop(opened);
    assert!(visible(&dir).is_empty(), "{:?}", visible(&dir));
    let hidden = std::fs::read_dir(&dir).expect("listable").count();
    assert_eq!(hidden, 0, "staging and lock files are cleaned");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unusable_output_directories_are_refused_before_any_work() {
    let dir = temp_dir("unusable");
    let file = write_in(&dir, "a-file", "x");
    let foreign = dir.join("documents");
    std::fs::create_dir(&foreign).expect("mkdir");
    std::fs::write(foreign.join("notes.txt"), "precious").expect("write");
    // A billion episodes per run: these would not end if the check came after the work.
    let mut targets = vec![
        (file.clone(), "not a directory"),
        (file.join("below"), "a-file: exists and is not a directory"),
        (foreign.clone(), "does not hold learnpnp results"),
    ];
    if cfg!(target_os = "linux") {
        // Not writable even by root.
        targets.push((PathBuf::from("/proc/learnpnp-results"), "/proc"));
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let locked = dir.join("read-only");
        std::fs::create_dir(&locked).expect("mkdir");
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).expect("chmod");
        // Root writes anyway: only check where permissions apply.
        if std::fs::write(locked.join("probe"), "x").is_err() {
            targets.push((locked.join("run"), "read-only"));
        }
    }
    for (target, expected) in targets {
        let out = learnpnp(&as_strs(&experiment_args(&target, 1, 1_000_000_000)));
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{}: {err}", target.display());
        assert!(err.contains(expected), "{}: {err}", target.display());
    }
    assert_eq!(
        std::fs::read_to_string(foreign.join("notes.txt")).expect("kept"),
        "precious"
    );
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(dir.join("read-only"), std::fs::Permissions::from_mode(0o755));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The files whose bytes identify a run (the summary's timing aside).
const RESULT_FILES: [&str; 5] = ["curve.csv", "runs.csv", "episodes.csv", "traces.csv", "values.bin"];

/// Which reference set `out` is, asserting it is exactly one of them.
fn which_set(out: &Path, references: &[(u64, PathBuf)]) -> u64 {
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary")).expect("json");
    let seed = summary["spec"]["seed"].as_u64().expect("seed");
    let (_, reference) = references.iter().find(|(s, _)| *s == seed).expect("a known seed");
    for file in RESULT_FILES {
        assert_eq!(
            std::fs::read(out.join(file)).expect("present"),
            std::fs::read(reference.join(file)).expect("present"),
            "{file} is not from the run of summary.json (seed {seed})"
        );
    }
    assert!(out.join("manifest.json").is_file());
    seed
}

#[test]
fn kills_at_any_moment_never_leave_a_mix_of_two_runs() {
    let dir = temp_dir("kills");
    let references: Vec<(u64, PathBuf)> = [1, 2].map(|seed| (seed, dir.join(format!("ref{seed}")))).to_vec();
    let mut duration = Duration::ZERO;
    for (seed, path) in &references {
        let start = Instant::now();
        let o = learnpnp(&as_strs(&experiment_args(path, *seed, 200)));
        duration = duration.max(start.elapsed());
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
    let out = dir.join("run");
    let o = learnpnp(&as_strs(&experiment_args(&out, 1, 200)));
    assert!(o.status.success(), "{}", text(&o.stderr));
    // Seed 2 replaces seed 1, killed at moments spread over its whole life
    // (the final writing step included) and beyond.
    let steps = 24u32;
    let mut seen = Vec::new();
    for i in 0..=steps {
        let mut child = spawn(&as_strs(&experiment_args(&out, 2, 200)));
        std::thread::sleep(duration * i / (steps - 4));
        let _ = child.kill();
        child.wait().expect("wait");
        seen.push(which_set(&out, &references));
        assert_eq!(
            visible(&dir),
            ["ref1", "ref2", "run"],
            "nothing but whole result directories is visible"
        );
        // Back to seed 1 for the next kill when seed 2 got through.
        if seen.last() == Some(&2) {
            let o = learnpnp(&as_strs(&experiment_args(&out, 1, 200)));
            assert!(o.status.success(), "{}", text(&o.stderr));
        }
    }
    assert_eq!(seen[0], 1, "killed at once, the run changed nothing");
    let o = learnpnp(&as_strs(&experiment_args(&out, 2, 200)));
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(which_set(&out, &references), 2);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Learning flags of an experiment long enough to be interrupted.
fn long_experiment(out: &Path, seed: &str, resume: bool) -> Vec<String> {
    let mut args: Vec<String> = [
        "experiment",
        "parr-russell",
        "--algo",
        "eps-sosmc",
        "--runs",
        "24",
        "--episodes",
        "2000",
        "--eval-every",
        "100",
        "--threads",
        "2",
        "--seed",
        seed,
        "--out",
        out.to_str().expect("utf-8 path"),
    ]
    .map(String::from)
    .to_vec();
    if resume {
        args.push("--resume".into());
    }
    args
}

#[cfg(unix)]
#[test]
fn a_terminated_experiment_keeps_its_runs_and_resumes_to_the_same_numbers() {
    let dir = temp_dir("sigterm");
    let reference = dir.join("reference");
    let start = Instant::now();
    let o = learnpnp(&as_strs(&long_experiment(&reference, "5", false)));
    let duration = start.elapsed();
    assert!(o.status.success(), "{}", text(&o.stderr));

    let out = dir.join("run");
    let child = spawn(&as_strs(&long_experiment(&out, "5", false)));
    // The lock exists once the handlers are installed and the work begins.
    wait_for(&dir.join(".run.lock"));
    std::thread::sleep(duration * 2 / 5);
    let pid = libc::pid_t::try_from(child.id()).expect("a pid");
    // SAFETY: sending a signal to our own child process.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGTERM) }, 0);
    let interrupted = child.wait_with_output().expect("wait");
    let err = text(&interrupted.stderr);
    match interrupted.status.code() {
        Some(143) if out.exists() => {
            assert!(err.contains("partial result") && err.contains("--resume"), "{err}");
            let summary: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("summary"))
                    .expect("json");
            assert_eq!(summary["complete"], false);
            let kept = summary["runs_completed"].as_u64().expect("a count");
            assert!((1..24).contains(&kept), "{kept} runs kept");
            let runs = std::fs::read_to_string(out.join("runs.csv")).expect("runs.csv");
            assert_eq!(
                runs.lines().count() as u64,
                1 + kept * 21,
                "21 evaluations per kept run"
            );
            // Readers say what they read.
            let svg = dir.join("partial.svg");
            let o = learnpnp(&["plot", out.to_str().expect("utf-8"), "-o", svg.to_str().expect("utf-8")]);
            assert!(o.status.success(), "{}", text(&o.stderr));
            assert!(text(&o.stderr).contains("partial result"), "{}", text(&o.stderr));
            assert!(
                std::fs::read_to_string(&svg)
                    .expect("svg")
                    .contains(&format!("partial: {kept} of 24 runs"))
            );
        }
        Some(143) => assert!(err.contains("before any run completed"), "{err}"),
        // The machine was fast enough to finish first.
        Some(0) => {}
        other => panic!("exit status {other:?}: {err}"),
    }

    // Resuming with other parameters is refused, and changes nothing.
    if out.exists() {
        let o = learnpnp(&as_strs(&long_experiment(&out, "6", true)));
        assert_eq!(o.status.code(), Some(2));
        assert!(text(&o.stderr).contains("another experiment"), "{}", text(&o.stderr));
    }
    let o = learnpnp(&as_strs(&long_experiment(&out, "5", true)));
    assert!(o.status.success(), "{}", text(&o.stderr));
    for file in RESULT_FILES.iter().chain(&["curve.csv"]) {
        assert_eq!(
            std::fs::read(out.join(file)).expect("present"),
            std::fs::read(reference.join(file)).expect("present"),
            "{file}: the resumed experiment differs from the uninterrupted one"
        );
    }
    let o = learnpnp(&as_strs(&long_experiment(&out, "5", true)));
    assert!(o.status.success());
    assert!(text(&o.stdout).contains("nothing to do"), "{}", text(&o.stdout));
    let _ = std::fs::remove_dir_all(&dir);
}
