//! Helpers shared by the test binaries of every crate in the workspace (each
//! crate's `tests/main.rs` includes this file as its `util` module).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use learnpnp::condition::{AtomId, BitKnowledgeBase, KnowledgeBase};
use learnpnp::executor::{Action, World};
use learnpnp::experiment::runner::{Completed, ExperimentOutput, RunOptions, run_experiment};
use learnpnp::experiment::spec::ExperimentSpec;
use learnpnp::learning::{Assessment, ExploitPolicy, Schedule, Sigma, SoSmcConfig, StepSize, Unestimated};
use learnpnp::net::{PetriNet, PlaceNode, TransitionNode};
use learnpnp::plan::{PlaceRef, PlanBuilder};
use proptest::test_runner::{Config as ProptestConfig, FileFailurePersistence};

/// The workspace's root directory (where `plans/` and `tests/fixtures/` are).
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .find(|dir| dir.join("Cargo.lock").exists())
        .expect("the workspace root holds Cargo.lock")
}

/// The path of the shipped plan file `plans/FILE`.
pub fn shipped(file: &str) -> PathBuf {
    root().join("plans").join(file)
}

/// The path of the shipped plan file `plans/FILE`, as a command-line argument.
pub fn shipped_arg(file: &str) -> String {
    shipped(file).display().to_string()
}

/// The path of `tests/fixtures/RELATIVE`.
pub fn fixture(relative: &str) -> PathBuf {
    root().join("tests/fixtures").join(relative)
}

/// A fresh, empty directory for one test: unique within the test binary
/// (every call gets its own) and across concurrent runs (the process id).
pub fn temp_dir(tag: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("learnpnp-test-{}-{n}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    dir
}

/// Writes `contents` to the file `name` in `dir`; returns the file's path.
pub fn write_in(dir: &Path, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let file = dir.join(name);
    std::fs::write(&file, contents).expect("a file in the test's directory");
    file
}

/// SoSMC crediting each option with the first-visit return that followed it:
/// random choices for `initial_phase` episodes, then ε-greedy with ε = 0.1, a
/// constant step size of 0.1, no assessment.
pub fn plain_sosmc(initial_phase: u64) -> SoSmcConfig {
    SoSmcConfig {
        gamma: 1.0,
        initial_phase,
        sigma: Sigma::EpsilonGreedy,
        initial_parameter: Schedule::constant(1.0),
        assessing_parameter: Schedule::constant(0.1),
        assessment: Assessment::Never,
        step_size: StepSize::Constant(0.1),
        initial_value: f64::NEG_INFINITY,
        threshold: None,
        unestimated: Unestimated::AsBest,
        exploit: ExploitPolicy::Greedy,
    }
}

/// A plan named `name` that begins by starting the action `look`: its
/// builder, the place of `look` running and the goal place (the test ends the action).
pub fn looking(name: &str) -> (PlanBuilder, PlaceRef, PlaceRef) {
    let mut b = PlanBuilder::new(name);
    let init = b.initial_place("init");
    let exec = b.place("look.exec");
    b.transition("look.start", &[(init, 1)], &[(exec, 1)]);
    let goal = b.goal_place();
    (b, exec, goal)
}

/// Output bytes as text (lossy).
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs `spec` with `threads` workers, no progress bar and no stop flag.
pub fn run_quietly(spec: &ExperimentSpec, threads: usize) -> ExperimentOutput {
    let options = RunOptions {
        threads,
        progress: false,
        stop: None,
        only: None,
        feed: None,
    };
    run_experiment(spec, options, Completed::default()).expect("the experiment runs")
}

/// The shipped plan schemas (`plans/NAME.schema`).
pub const SHIPPED_SCHEMAS: [&str; 8] = [
    "football",
    "football_choice",
    "penalty_kick",
    "penalty_kick_restructured",
    "parr_russell",
    "sutton",
    "keepaway_pass",
    "keepaway_position",
];

/// A world that logs every action call and pays a fixed reward per step.
#[derive(Default)]
pub struct LogWorld {
    /// The atoms' truth.
    pub kb: BitKnowledgeBase,
    /// What the actions were told, in order (`start act_2`, `step act_2`, ...).
    pub lines: Vec<String>,
    /// The reward of every step.
    pub reward_per_step: f64,
}

impl KnowledgeBase for LogWorld {
    fn holds(&self, atom: AtomId) -> bool {
        self.kb.holds(atom)
    }
}

impl World for LogWorld {
    fn take_reward(&mut self) -> f64 {
        self.reward_per_step
    }
}

/// An action lasting `n` steps, named `name_n`, that logs its calls; its
/// declared condition 0 holds once it has stepped.
pub struct Timed {
    name: String,
    steps: u32,
    done: u32,
}

impl Timed {
    /// The action called `name`.
    pub fn new(name: &str) -> Self {
        let steps = name.rsplit('_').next().and_then(|n| n.parse().ok()).unwrap_or(1);
        Timed {
            name: name.to_string(),
            steps,
            done: 0,
        }
    }
}

impl Action<LogWorld> for Timed {
    fn reset(&mut self) {
        self.done = 0;
    }
    fn start(&mut self, w: &mut LogWorld) {
        self.done = 0;
        w.lines.push(format!("start {}", self.name));
    }
    fn step(&mut self, w: &mut LogWorld) {
        self.done += 1;
        w.lines.push(format!("step {}", self.name));
    }
    fn end(&mut self, w: &mut LogWorld) {
        w.lines.push(format!("end {}", self.name));
    }
    fn interrupt(&mut self, w: &mut LogWorld) {
        w.lines.push(format!("interrupt {}", self.name));
    }
    fn finished(&self, _: &LogWorld) -> bool {
        self.done >= self.steps
    }
    fn condition(&self, index: usize, _: &LogWorld) -> bool {
        index == 0 && self.done >= 1
    }
}

/// A net as a file would give it: places `(id, label, initial tokens)`,
/// transitions `(id, label)`, arcs `(source, target, weight)` (ids `a0`, `a1`, ...).
pub fn net(places: &[(&str, &str, u8)], transitions: &[(&str, &str)], arcs: &[(&str, &str, u8)]) -> PetriNet {
    let places = places
        .iter()
        .map(|&(id, label, initial)| PlaceNode {
            id: id.into(),
            label: label.into(),
            initial,
            position: None,
        })
        .collect();
    let transitions = transitions
        .iter()
        .map(|&(id, label)| TransitionNode {
            id: id.into(),
            label: label.into(),
            position: None,
        })
        .collect();
    let ids: Vec<String> = (0..arcs.len()).map(|i| format!("a{i}")).collect();
    let arcs: Vec<_> = arcs
        .iter()
        .zip(&ids)
        .map(|(&(s, t, w), id)| (id.as_str(), s, t, w))
        .collect();
    PetriNet::new("test", places, transitions, &arcs).expect("a well-formed net")
}

/// Proptest's settings with `cases` cases, failures kept beside the source
/// (`proptest-regressions/`) so that a found case is re-run first.
pub fn proptest_config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions"))),
        ..ProptestConfig::default()
    }
}
