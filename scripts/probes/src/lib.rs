//! Measurement probes behind `docs/results/RESULTS.md`: programs that print
//! figures, kept as examples of this package so that `cargo test` keeps them
//! compiling (`scripts/README.md` lists what each one measures).
//!
//! `cargo run --release -p learnpnp-probes --example NAME -- [ARGS]`.

pub mod args;
