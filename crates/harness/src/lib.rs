//! learnpnp's test and measurement harness around the multi-process system
//! (the crate `learnpnp-system`): soaks that run the system for a set time
//! while sampling every process, chaos that injects faults into them, the
//! latency and world benchmarks. The binary `learnpnp-soak` runs them; the
//! product's own commands are `learnpnp-supervisor`'s.
//!
//! - [`soak`]: the soak observer, its samples, report and verdict;
//! - [`chaos`] (with [`garbage`] and [`load`]): the faults a soak injects, the
//!   garbage a foreign process publishes on a run's services, and CPU load
//!   beside a run;
//! - [`bench_latency`], [`bench_world`]: the benchmarks.

#![deny(missing_docs)]

/// The latency benchmark.
pub mod bench_latency;
/// How the generic path's cost grows with the agents.
pub mod bench_world;
/// Faults injected at seeded random times during a soak.
pub mod chaos;
/// Garbage on a run's services, published as a foreign process would.
pub mod garbage;
/// CPU load beside a run.
pub mod load;
/// Soak runs.
pub mod soak;

use learnpnp_system::multiprocess::supervisor::SupervisorError;

/// A JSON error about `what`, as the supervisor reports it.
fn json_error(what: &'static str) -> impl FnOnce(serde_json::Error) -> SupervisorError {
    move |source| SupervisorError::Json {
        what: what.to_string(),
        source,
    }
}
