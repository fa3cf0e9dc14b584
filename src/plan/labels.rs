//! The label languages of places and transitions (see `shared/reference/pnp-format.md`).

/// Splits a label on whitespace outside `()` and `[]`; a `[` that starts inside a
/// word also starts a new token (`goto.end[done]` is `goto.end` and `[done]`).
/// Returns `None` when brackets do not balance.
pub(crate) fn split_tokens(label: &str) -> Option<Vec<&str>> {
    let mut tokens = Vec::new();
    let mut depth = 0usize;
    let mut start: Option<usize> = None;
    for (i, c) in label.char_indices() {
        match c {
            '(' | '[' => {
                if c == '['
                    && depth == 0
                    && let Some(s) = start.take()
                {
                    tokens.push(&label[s..i]);
                }
                if start.is_none() {
                    start = Some(i);
                }
                depth += 1;
            }
            ')' | ']' => {
                depth = depth.checked_sub(1)?;
                if start.is_none() {
                    start = Some(i);
                }
            }
            c if c.is_whitespace() && depth == 0 => {
                if let Some(s) = start.take() {
                    tokens.push(&label[s..i]);
                }
            }
            _ => {
                if start.is_none() {
                    start = Some(i);
                }
            }
        }
    }
    if depth != 0 {
        return None;
    }
    if let Some(s) = start {
        tokens.push(&label[s..]);
    }
    Some(tokens)
}

/// What a place label says.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct PlaceLabel {
    /// The action or sub-plan whose execution place this is.
    pub exec: Option<String>,
    /// Tokens this place holds in a goal marking.
    pub goal: Option<u8>,
    /// Tokens this place holds in a fail marking.
    pub fail: Option<u8>,
}

/// Why a place label is malformed: the offending token and what was expected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct LabelError {
    /// The token.
    pub token: String,
    /// What is wrong with it.
    pub(crate) reason: String,
}

fn label_error(token: &str, reason: impl Into<String>) -> LabelError {
    LabelError {
        token: token.to_string(),
        reason: reason.into(),
    }
}

/// The action name of an execution-place token (`X.exec`, `X.ex`, legacy `ex.X`).
fn exec_name(token: &str) -> Option<&str> {
    token
        .strip_suffix(".exec")
        .or_else(|| token.strip_suffix(".ex"))
        .or_else(|| token.strip_prefix("ex."))
}

/// Parses `goal` / `goal(n)` (or `fail`...) after `keyword`; `None` if the token is not one.
fn marking_token(token: &str, keyword: &str) -> Option<Result<u8, LabelError>> {
    let rest = token.strip_prefix(keyword)?;
    if rest.is_empty() {
        return Some(Ok(1));
    }
    let inner = rest.strip_prefix('(').and_then(|r| r.strip_suffix(')'));
    Some(match inner.map(|n| n.trim().parse::<u8>()) {
        Some(Ok(n)) if n > 0 => Ok(n),
        _ => Err(label_error(
            token,
            format!("expected '{keyword}' or '{keyword}(n)' with 1 <= n <= 255"),
        )),
    })
}

/// Parses a place label.
pub(crate) fn parse_place_label(label: &str) -> Result<PlaceLabel, LabelError> {
    let tokens = split_tokens(label).ok_or_else(|| label_error(label, "unbalanced brackets"))?;
    let mut out = PlaceLabel::default();
    for token in tokens {
        if let Some(name) = exec_name(token) {
            if name.is_empty() {
                return Err(label_error(token, "an execution place needs an action name"));
            }
            if out.exec.replace(name.to_string()).is_some() {
                return Err(label_error(token, "a second execution token"));
            }
        } else if let Some(n) = marking_token(token, "goal") {
            if out.goal.replace(n?).is_some() {
                return Err(label_error(token, "a second goal token"));
            }
        } else if let Some(n) = marking_token(token, "fail")
            && out.fail.replace(n?).is_some()
        {
            return Err(label_error(token, "a second fail token"));
        }
    }
    Ok(out)
}

/// A function a transition calls on an action or sub-plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Function {
    /// Start it (its execution place gets a token).
    Start,
    /// End it normally.
    End,
    /// Interrupt it.
    Interrupt,
    /// Resume it after an interrupt.
    Resume,
    /// End it as failed.
    Fail,
}

impl Function {
    /// The function named by a label suffix (`start`, `end`, `interrupt`/`interr`, `resume`/`res`, `fail`).
    pub(crate) fn from_suffix(s: &str) -> Option<Self> {
        Some(match s {
            "start" => Function::Start,
            "end" => Function::End,
            "interrupt" | "interr" => Function::Interrupt,
            "resume" | "res" => Function::Resume,
            "fail" => Function::Fail,
            _ => return None,
        })
    }

    /// Its canonical label suffix.
    pub(crate) fn as_str(self) -> &'static str {
        match self {
            Function::Start => "start",
            Function::End => "end",
            Function::Interrupt => "interrupt",
            Function::Resume => "resume",
            Function::Fail => "fail",
        }
    }

    /// Whether a bare token refers to the action of an output (true) or input place.
    pub(crate) fn binds_output(self) -> bool {
        matches!(self, Function::Start | Function::Resume)
    }
}

/// One token of a transition label.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum TransitionToken<'a> {
    /// `[guard]`: the text between the brackets.
    Guard(&'a str),
    /// `A.f`: function `f` on action `A`.
    Call(&'a str, Function),
    /// A bare `f`, referring to the adjacent execution place.
    BareCall(Function),
    /// A name with no meaning (`T1`, `fork`).
    Name(&'a str),
    /// `A.x` with an `x` that is no function.
    UnknownFunction(&'a str),
}

/// Classifies the tokens of a transition label; `None` when brackets do not balance.
pub(crate) fn transition_tokens(label: &str) -> Option<Vec<TransitionToken<'_>>> {
    let tokens = split_tokens(label)?;
    Some(
        tokens
            .into_iter()
            .map(|t| {
                if let Some(inner) = t.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
                    TransitionToken::Guard(inner)
                } else if let Some(f) = Function::from_suffix(t) {
                    TransitionToken::BareCall(f)
                } else if let Some((action, suffix)) = t.rsplit_once('.') {
                    match Function::from_suffix(suffix) {
                        Some(f) if !action.is_empty() => TransitionToken::Call(action, f),
                        _ => TransitionToken::UnknownFunction(t),
                    }
                } else {
                    TransitionToken::Name(t)
                }
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_outside_brackets() {
        assert_eq!(
            split_tokens("goto.end [and a b]").unwrap(),
            vec!["goto.end", "[and a b]"]
        );
        assert_eq!(
            split_tokens("goto.end[done] x").unwrap(),
            vec!["goto.end", "[done]", "x"]
        );
        assert_eq!(split_tokens("  goal(2)  p ").unwrap(), vec!["goal(2)", "p"]);
        assert_eq!(split_tokens("[a (b c)]").unwrap(), vec!["[a (b c)]"]);
        assert!(split_tokens("[a").is_none());
        assert!(split_tokens("a]").is_none());
    }

    #[test]
    fn place_labels() {
        let l = parse_place_label("gotopose_6_2_0.exec").unwrap();
        assert_eq!(l.exec.as_deref(), Some("gotopose_6_2_0"));
        assert_eq!(parse_place_label("ex.kick").unwrap().exec.as_deref(), Some("kick"));
        assert_eq!(
            parse_place_label("r1#kick.ex").unwrap().exec.as_deref(),
            Some("r1#kick")
        );
        assert_eq!(parse_place_label("goal").unwrap().goal, Some(1));
        assert_eq!(
            parse_place_label("goalie.exec").unwrap().exec.as_deref(),
            Some("goalie")
        );
        assert_eq!(parse_place_label("goal(3)").unwrap().goal, Some(3));
        assert_eq!(parse_place_label("fail").unwrap().fail, Some(1));
        assert_eq!(parse_place_label("p1").unwrap(), PlaceLabel::default());
        for bad in ["goalX", "goal(x)", "goal(0)", "goal(", "fail(300)", ".exec"] {
            let e = parse_place_label(bad).unwrap_err();
            assert!(!e.token.is_empty(), "{bad}");
        }
    }

    #[test]
    fn transition_labels() {
        let toks = transition_tokens("goto.interrupt [obstacle] T1 start a.res b.strat").unwrap();
        assert_eq!(
            toks,
            vec![
                TransitionToken::Call("goto", Function::Interrupt),
                TransitionToken::Guard("obstacle"),
                TransitionToken::Name("T1"),
                TransitionToken::BareCall(Function::Start),
                TransitionToken::Call("a", Function::Resume),
                TransitionToken::UnknownFunction("b.strat"),
            ]
        );
        assert_eq!(
            transition_tokens("gotopose_6.2.end").unwrap(),
            vec![TransitionToken::Call("gotopose_6.2", Function::End)]
        );
    }
}
