//! The command line of the run's child processes (`learnpnp-sim`,
//! `learnpnp-agent`): the clap arguments that carry a [`RunContext`](crate::multiprocess::RunContext), as the
//! supervisor writes them ([`RunContext::to_args`](crate::multiprocess::RunContext::to_args)). The library's types know
//! nothing of clap; the binaries flatten [`RunContextArgs`](crate::child_args::RunContextArgs) into their own
//! arguments and convert it.

use std::path::PathBuf;

use clap::Args;
use learnpnp::named::Named;

use crate::ipc::wait::WaitStrategy;
use crate::multiprocess::{Clock, RunContext};

/// The arguments that give a child process its [`RunContext`].
#[derive(Debug, Clone, Args)]
pub struct RunContextArgs {
    /// The run's id (every message carries it).
    #[arg(long)]
    pub run_id: u64,
    /// The run's index among the experiment's runs (it derives the seeds).
    #[arg(long, default_value_t = 0)]
    pub run: usize,
    /// The run's iceoryx2 prefix.
    #[arg(long)]
    pub(crate) ipc_prefix: String,
    /// How the simulator's clock advances.
    #[arg(long, value_parser = Clock::from_name, default_value = "lockstep")]
    pub clock: Clock,
    /// How processes wait for messages.
    #[arg(long, value_parser = WaitStrategy::from_name, default_value = "yield")]
    pub wait: WaitStrategy,
    /// The experiment (as `summary.json` of a run holds it, under `spec`, or on its own).
    #[arg(long)]
    pub spec: PathBuf,
    /// Where the process writes its files (histograms, results, checkpoints).
    #[arg(long)]
    pub(crate) work_dir: PathBuf,
    /// The run has a view: publish the agent's live feed.
    #[arg(long)]
    pub feed: bool,
}

impl From<RunContextArgs> for RunContext {
    fn from(args: RunContextArgs) -> Self {
        RunContext {
            run_id: args.run_id,
            run: args.run,
            ipc_prefix: args.ipc_prefix,
            clock: args.clock,
            wait: args.wait,
            spec: args.spec,
            work_dir: args.work_dir,
            feed: args.feed,
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Parser)]
    struct Child {
        #[command(flatten)]
        context: RunContextArgs,
    }

    /// What the supervisor writes on a child's command line is what the child reads.
    #[test]
    fn the_supervisors_arguments_parse_back_into_the_same_context() {
        for (clock, wait, feed) in [
            (Clock::Lockstep, WaitStrategy::Yield, false),
            (Clock::Realtime, WaitStrategy::Hybrid, true),
            (Clock::Lockstep, WaitStrategy::Spin, true),
            (Clock::Realtime, WaitStrategy::Block, false),
        ] {
            let context = RunContext {
                run_id: u64::MAX - 3,
                run: 7,
                ipc_prefix: "lpnp_abc_".into(),
                clock,
                wait,
                spec: "/tmp/a b/spec.json".into(),
                work_dir: "/tmp/run-7".into(),
                feed,
            };
            let args = std::iter::once("child".into()).chain(context.to_args());
            let parsed: RunContext = Child::try_parse_from(args).unwrap().context.into();
            assert_eq!(parsed, context);
        }
    }
}
