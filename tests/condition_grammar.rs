//! Property tests of the guard grammar: every condition prints to text that
//! parses back to it, and arbitrary text parses or is refused with an error
//! that points at a real token of it.

use learnpnp::condition::{Expr, parse_condition};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

/// `cases` cases; failures are saved next to this file (integration tests have
/// no lib.rs for proptest's default to find).
fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions"))),
        ..ProptestConfig::default()
    }
}

/// An atom of the grammar, never an operator.
fn atom() -> impl Strategy<Value = String> {
    "[a-zA-Z][-@a-zA-Z0-9._#{,}<>\"+^/]{0,6}".prop_filter("not an operator", |a| {
        !matches!(a.to_lowercase().as_str(), "and" | "or" | "not")
    })
}

/// Conditions up to four levels deep; `and`/`or` have at least two operands.
fn expr() -> impl Strategy<Value = Expr> {
    let leaf = atom().prop_map(Expr::Atom);
    leaf.prop_recursive(4, 24, 4, |inner| {
        prop_oneof![
            inner.clone().prop_map(|e| Expr::Not(Box::new(e))),
            prop::collection::vec(inner.clone(), 2..4).prop_map(Expr::And),
            prop::collection::vec(inner, 2..4).prop_map(Expr::Or),
        ]
    })
}

/// Text of the grammar's alphabet, with fragments that stress it.
fn text() -> impl Strategy<Value = String> {
    prop::collection::vec(
        prop_oneof![
            Just("(".to_string()),
            Just(")".to_string()),
            Just(" ".to_string()),
            Just("\t".to_string()),
            Just("and".to_string()),
            Just("OR".to_string()),
            Just("not".to_string()),
            atom(),
            "[0-9!$%&*]{1,2}",
            "\\PC{1,2}",
        ],
        0..16,
    )
    .prop_map(|parts| parts.concat())
}

proptest! {
    #![proptest_config(config(500))]

    #[test]
    fn printed_conditions_parse_back(e in expr()) {
        let text = e.to_guard_text();
        prop_assert_eq!(parse_condition(&text).expect("printed text parses"), e.clone(), "{}", text);
        // Redundant parentheses and spaces change nothing.
        let wrapped = format!("  ( {text} )\t");
        prop_assert_eq!(parse_condition(&wrapped).expect("wrapped text parses"), e);
    }

    #[test]
    fn errors_point_at_a_real_token(text in text()) {
        match parse_condition(&text) {
            Ok(e) => {
                // What parses prints to text that parses to the same condition.
                prop_assert_eq!(parse_condition(&e.to_guard_text()).expect("reprint parses"), e);
            }
            Err(err) => {
                prop_assert!(err.offset <= text.len(), "{err}");
                prop_assert_eq!(&err.text, &text);
                if err.token != "<end>" {
                    prop_assert!(
                        text[err.offset..].starts_with(&err.token),
                        "token '{}' not at offset {} of '{}'", err.token, err.offset, text
                    );
                }
            }
        }
    }
}

#[test]
fn nesting_beyond_the_bound_is_refused_and_within_it_parses() {
    let nested = |depth: usize| format!("{}a{}", "(not ".repeat(depth), ")".repeat(depth));
    assert!(parse_condition(&nested(20)).is_ok());
    let err = parse_condition(&nested(200)).expect_err("too deep");
    assert!(err.message.contains("nested too deeply"), "{err}");
}
