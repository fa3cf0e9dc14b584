//! The flags of `learnpnp experiment` and of the multi-process supervisor:
//! the core crate's [`ExperimentOptions`](learnpnp::experiment::options::ExperimentOptions), which declares each of them.

use learnpnp::experiment::options::ExperimentOptions;
pub use learnpnp::experiment::options::named;

/// Parses experiment flags (`["--algo", "sarsa0", ...]`, without a program
/// name or domain) as `learnpnp experiment` does.
pub fn parse_experiment_flags(flags: &[&str]) -> Result<ExperimentOptions, clap::Error> {
    #[derive(clap::Parser)]
    struct Flags {
        #[command(flatten)]
        options: ExperimentOptions,
    }
    let flags = <Flags as clap::Parser>::try_parse_from(std::iter::once("learnpnp").chain(flags.iter().copied()))?;
    Ok(flags.options)
}
