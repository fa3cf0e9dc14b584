//! Property tests of the guard grammar: every condition prints to text that
//! parses back to it, and arbitrary text parses or is refused with an error
//! that points at a real token of it and shows how conditions are written.

use learnpnp::condition::{Expr, PREFIX_FORM, parse_condition};
use learnpnp::plan::AllowedAtoms;
use learnpnp::plan_file::load_plan;
use proptest::prelude::*;

/// `cases` cases; failures are saved next to this file (integration tests have
/// no lib.rs for proptest's default to find).
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
    #![proptest_config(crate::util::proptest_config(500))]

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
                // Every error shows the prefix form, operator first.
                let hint = err.hint();
                prop_assert!(hint.contains(" first: ["), "{}", hint);
                prop_assert!(err.to_string().ends_with(&format!("; {hint}")), "{}", err);

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

#[test]
fn an_infix_operator_is_named_and_the_prefix_form_shown() {
    let err = parse_condition("ballSeen and ballClose").expect_err("infix");
    assert_eq!(err.token, "and");
    assert_eq!(
        err.to_string(),
        "expected ')' at 'and' (offset 9 of 'ballSeen and ballClose'); 'and' is an operator, \
         written first: [and ballSeen ballClose], not [ballSeen and ballClose]"
    );
    // C's operators, and an infix operator inside parentheses.
    let err = parse_condition("free && near").expect_err("infix");
    assert!(
        err.to_string()
            .contains("the operator is 'and', written first: [and free near]"),
        "{err}"
    );
    let err = parse_condition("and c (a or b)").expect_err("infix inside parentheses");
    assert_eq!((err.token.as_str(), err.offset), ("or", 9));
    assert!(
        err.to_string()
            .contains("'or' is an operator, written first: [or a b], not [a or b]"),
        "{err}"
    );
    // Anything else shows the grammar in general.
    for text in ["and a", "not a b", "a b", "(a", "3x", "a)"] {
        let err = parse_condition(text).expect_err("malformed");
        assert!(err.to_string().ends_with(&format!("; {PREFIX_FORM}")), "{err}");
    }
}

#[test]
fn a_plan_file_with_an_infix_guard_names_the_file_transition_and_token() {
    let dir = crate::util::temp_dir("infix-guard");
    let path = dir.join("infix.pnml");
    std::fs::write(
        &path,
        "<pnml><net id='n'>\
         <place id='p1'><name><value>start</value></name>\
         <initialMarking><value>Default,1</value></initialMarking></place>\
         <place id='p2'><name><value>goal</value></name></place>\
         <transition id='t1'><name><value>[ballSeen and ballClose]</value></name></transition>\
         <arc id='a1' source='p1' target='t1'/><arc id='a2' source='t1' target='p2'/>\
         </net></pnml>",
    )
    .expect("write");
    let err = load_plan(&path, AllowedAtoms::Open).expect_err("an infix guard");
    assert_eq!(err.element().as_deref(), Some("t1"));
    assert_eq!(err.token().as_deref(), Some("and"));
    let text = err.to_string();
    for part in [
        "infix.pnml",
        "transition 't1'",
        "broken guard: expected ')' at 'and'",
        "[and ballSeen ballClose], not [ballSeen and ballClose]",
    ] {
        assert!(text.contains(part), "'{part}' not in: {text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
