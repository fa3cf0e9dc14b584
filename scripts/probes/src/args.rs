//! The probes' command line: their one optional argument, a
//! positive count, and their exit code.

use std::process::ExitCode;

use anyhow::{Context, Result, bail};

/// Success, or exit code 2 with the error and its causes on standard error.
pub fn exit_code(result: Result<()>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// The count given as the only argument (`default` without one), refused
/// unless it is a positive integer; `usage` names the program and its argument.
pub fn positive_count(name: &str, default: u64, usage: &str) -> Result<u64> {
    let mut args = std::env::args().skip(1);
    let n = match args.next() {
        Some(a) => a
            .parse()
            .ok()
            .filter(|&n| n > 0)
            .with_context(|| format!("{name} must be a positive integer, got `{a}`"))?,
        None => default,
    };
    if let Some(extra) = args.next() {
        bail!("unexpected argument `{extra}` (usage: {usage})");
    }
    Ok(n)
}
