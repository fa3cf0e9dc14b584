//! The experiment flags (shared by every entry point): every number is
//! range-checked when parsed, with the valid range in the message; property
//! tests over random values and random argument lists.

use learnpnp::experiment::options::{DomainName, ExperimentOptions};
use learnpnp::experiment::ranges::{self, RealRange};
use proptest::prelude::*;

/// `cases` cases; failures are saved next to this file (integration tests have
/// no lib.rs for proptest's default to find).
fn parse(args: &[&str]) -> Result<ExperimentOptions, clap::Error> {
    learnpnp_flags::args::parse_experiment_flags(args)
}

/// The error text of refused flags.
fn refused(args: &[&str]) -> String {
    match parse(args) {
        Ok(_) => panic!("{args:?} accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn every_out_of_range_number_is_refused_with_its_range() {
    let cases: &[(&[&str], &str)] = &[
        (&["--alpha", "NaN"], "from 0 (excluded) to 1"),
        (&["--alpha", "5"], "from 0 (excluded) to 1"),
        (&["--alpha", "0"], "from 0 (excluded) to 1"),
        (&["--lambda", "7"], "from 0 to 1"),
        (&["--epsilon", "-1"], "from 0 to 1"),
        (&["--epsilon", "2"], "from 0 to 1"),
        (&["--epsilon", "inf"], "from 0 to 1"),
        (&["--epsilon", "0.5:1.5:100"], "from 0 to 1"),
        (&["--tau", "0"], "finite number above 0"),
        (&["--tau", "-2"], "finite number above 0"),
        (&["--tau", "inf"], "finite number above 0"),
        (&["--gamma", "2"], "from 0 to 1"),
        (&["--gamma", "-0.5"], "from 0 to 1"),
        (&["--step-size=-3"], "from 0 (excluded) to 1, or 'inverse'"),
        (&["--step-size", "1.5"], "from 0 (excluded) to 1, or 'inverse'"),
        (&["--alpha-min", "0"], "from 0 (excluded) to 1"),
        (&["--max-actions", "0"], "from 1 to 4294967295"),
        (&["--max-actions", "-5"], "from 1 to 4294967295"),
        (&["--runs", "0"], "from 1 to 100000"),
        (&["--episodes", "0"], "from 1 to 1000000000"),
        (&["--eval-every", "0"], "at least 1"),
        (&["--stage-length", "0"], "at least 1"),
        (&["--initial-value", "NaN"], "finite number or -inf"),
        (&["--initial-value", "inf"], "finite number or -inf"),
        (&["--initial-parameter", "-1"], "at least 0"),
        (&["--assess", "every:0"], "from 1 to"),
        (&["--threshold", "NaN:200"], "finite number"),
        (&["--threshold", "18:0"], "from 1 to"),
        (&["--hold-threshold", "-1"], "from 0 to 200"),
        (&["--lane-threshold", "1e9"], "from 0 to 200"),
        (&["--taker-threshold", "NaN"], "from 0 to 200"),
        (&["--seed", "-1"], "whole number"),
    ];
    for (args, range) in cases {
        let message = refused(args);
        assert!(message.contains(range), "{args:?}: {message}");
        assert!(
            message.contains(args[0].split('=').next().unwrap_or("")),
            "{args:?} names the flag: {message}"
        );
    }
}

#[test]
fn numbers_that_depend_on_each_other_are_checked_when_the_spec_is_built() {
    let spec = |args: &[&str], domain| parse(args).expect("parses").spec(domain);
    // An evaluation interval longer than the run would report the initial policy.
    let err = spec(
        &["--algo", "sarsa0", "--episodes", "100", "--eval-every", "200"],
        DomainName::ParrRussell,
    )
    .expect_err("eval-every beyond the run");
    assert!(
        err.to_string()
            .contains("eval-every: 200 is out of range: it must be a whole number from 1 to 100"),
        "{err}"
    );
    // Without --eval-every, the domain's interval is shortened to the run.
    let s = spec(&["--algo", "sarsa0", "--episodes", "7"], DomainName::Sutton).expect("valid");
    assert_eq!(s.protocol.eval_every, 7);
    // The initial-phase parameter is an epsilon for eps-sosmc, a temperature for soft-sosmc.
    let err = spec(
        &["--algo", "eps-sosmc", "--initial-parameter", "3"],
        DomainName::ParrRussell,
    )
    .expect_err("epsilon above 1");
    assert!(
        err.to_string().contains("initial-phase epsilon: 3 is out of range"),
        "{err}"
    );
    assert!(
        spec(
            &["--algo", "soft-sosmc", "--initial-parameter", "3"],
            DomainName::ParrRussell
        )
        .is_ok()
    );
    let err = spec(
        &["--algo", "soft-sosmc", "--initial-parameter", "0"],
        DomainName::ParrRussell,
    )
    .expect_err("temperature 0");
    assert!(err.to_string().contains("temperature"), "{err}");
}

/// Every flag that takes a real number, with its range.
fn real_flags() -> Vec<(&'static str, RealRange)> {
    vec![
        ("--gamma", ranges::GAMMA),
        ("--alpha", ranges::STEP),
        ("--lambda", ranges::LAMBDA),
        ("--epsilon", ranges::EPSILON),
        ("--tau", ranges::TEMPERATURE),
        ("--alpha-min", ranges::STEP),
        ("--hold-threshold", ranges::DISTANCE),
        ("--lane-threshold", ranges::DISTANCE),
        ("--taker-threshold", ranges::DISTANCE),
    ]
}

/// Real numbers around every range's ends, and the awkward ones.
fn real() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(1.0),
        Just(200.0),
        -2.0f64..3.0,
        -1e12f64..1e12,
        any::<f64>(),
    ]
}

proptest! {
    #![proptest_config(crate::util::proptest_config(300))]

    #[test]
    fn a_real_flag_is_accepted_exactly_when_in_range(flag in 0usize..9, value in real()) {
        let (name, range) = real_flags()[flag];
        let text = value.to_string();
        match parse(&[name, &text]) {
            Ok(_) => prop_assert!(range.contains(value), "{name} {text} accepted"),
            Err(e) => {
                prop_assert!(!range.contains(value), "{name} {text} refused: {e}");
                prop_assert!(e.to_string().contains(&range.describe()), "{e}");
            }
        }
    }

    #[test]
    fn a_count_flag_is_accepted_exactly_when_in_range(value in prop_oneof![Just(0u64), 0u64..300, any::<u64>()]) {
        let text = value.to_string();
        for (name, range) in [("--runs", ranges::RUNS), ("--episodes", ranges::EPISODES), ("--stage-length", ranges::STAGE_LENGTH)] {
            match parse(&[name, &text]) {
                Ok(_) => prop_assert!(range.check(value).is_ok(), "{name} {text} accepted"),
                Err(e) => prop_assert!(range.check(value).is_err() && e.to_string().contains(&range.describe()), "{e}"),
            }
        }
    }

    /// Random argument lists never panic: they parse, and then give a spec or a
    /// clear error, in every domain.
    #[test]
    fn random_flags_parse_or_are_refused(args in prop::collection::vec(prop_oneof![
        Just("--algo".to_string()), Just("eps-sosmc".to_string()), Just("soft-sosmc".to_string()),
        Just("sarsa-lambda".to_string()), Just("mcesp".to_string()), Just("q-learning".to_string()),
        Just("--alpha".to_string()), Just("--epsilon".to_string()), Just("--tau".to_string()),
        Just("--episodes".to_string()), Just("--eval-every".to_string()), Just("--runs".to_string()),
        Just("--assess".to_string()), Just("every:3".to_string()), Just("--threshold".to_string()),
        Just("--initial-parameter".to_string()), Just("--step-size".to_string()), Just("inverse".to_string()),
        Just("--initial-value".to_string()), Just("-inf".to_string()),
        real().prop_map(|v| v.to_string()),
        (0u64..100_000).prop_map(|v| v.to_string()),
        "[0-9:.e-]{1,8}",
        "\\PC{0,6}",
    ], 0..10)) {
        let argv: Vec<&str> = args.iter().map(String::as_str).collect();
        if let Ok(options) = parse(&argv) {
            for domain in [DomainName::ParrRussell, DomainName::Sutton, DomainName::PenaltyKick, DomainName::KeepawayPass] {
                match options.spec(domain) {
                    Ok(spec) => prop_assert!(spec.validate().is_ok()),
                    Err(e) => prop_assert!(!e.to_string().is_empty()),
                }
            }
        }
    }
}
