//! Linear plans as planners write them: IPC plan files (one grounded action
//! `(name arg ...)` per line) and PNPgen's one-line form (`a|30; b; c`).

use super::GenerateError;

/// One action of a linear plan, with PNPgen's optional timeout.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PlanStep {
    /// The action's name in the plan (`move_a_b` for `(move a b)`).
    pub action: String,
    /// Seconds after which the action is interrupted (`action|seconds`):
    /// PNPgen's timed action, run beside a `wait_<seconds>` action, whichever
    /// ends first interrupting the other.
    pub timeout: Option<u32>,
}

impl PlanStep {
    /// An action without a timeout.
    pub fn new(action: impl Into<String>) -> Self {
        PlanStep {
            action: action.into(),
            timeout: None,
        }
    }
}

impl std::fmt::Display for PlanStep {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.timeout {
            Some(t) => write!(f, "{}|{t}", self.action),
            None => f.write_str(&self.action),
        }
    }
}

/// Whether `name` can name an action in a plan's labels: a letter, then
/// letters, digits, `_` and `-` (no `.`, which separates an action from its
/// function or condition, and no space, which separates tokens).
pub fn is_action_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The plan action naming a grounded action: its name and arguments, lower
/// case, joined by `_` (`(move a b)` and `move(a, b)` are `move_a_b`).
pub fn grounded_name<'a>(name: &str, args: impl IntoIterator<Item = &'a str>) -> String {
    let mut out = name.to_ascii_lowercase();
    for a in args {
        out.push('_');
        out.push_str(&a.to_ascii_lowercase());
    }
    out
}

/// Reads an IPC plan file: one `(name arg ...)` per line, `;` starting a
/// comment, blank lines skipped; a temporal planner's `t: (...) [d]` is read
/// as its action. The action `(move a b)` becomes `move_a_b`.
pub fn parse_ipc_plan(text: &str) -> Result<Vec<PlanStep>, GenerateError> {
    let mut steps = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let body = raw.split(';').next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        let bad = |expected| GenerateError::BadStep {
            line,
            token: body.to_string(),
            expected,
        };
        // A temporal plan's `0.000: (a b) [1.000]`.
        let body = match (body.find(':'), body.find('(')) {
            (Some(colon), Some(open)) if colon < open => body[colon + 1..].trim(),
            _ => body,
        };
        let body = match (body.rfind(')'), body.rfind('[')) {
            (Some(close), Some(bracket)) if bracket > close => body[..bracket].trim(),
            _ => body,
        };
        let inner = body
            .strip_prefix('(')
            .and_then(|b| b.strip_suffix(')'))
            .ok_or_else(|| bad("an IPC plan has one '(name arg ...)' per line"))?;
        let mut words = inner.split_whitespace();
        let name = words.next().ok_or_else(|| bad("an action has a name"))?;
        let action = grounded_name(name, words);
        if !is_action_name(&action) {
            return Err(GenerateError::BadName { line, name: action });
        }
        steps.push(PlanStep::new(action));
    }
    Ok(steps)
}

/// Reads PNPgen's linear plan: actions separated by `;` (or spaces), each
/// with an optional `|seconds` timeout and PNPgen's optional `*` mark (read
/// and ignored); lines starting with `#` are comments, the others are read
/// one after another.
pub fn parse_pnpgen_line(text: &str) -> Result<Vec<PlanStep>, GenerateError> {
    let mut steps = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        if raw.trim_start().starts_with('#') {
            continue;
        }
        for token in raw
            .split(|c: char| c == ';' || c.is_whitespace())
            .filter(|t| !t.is_empty())
        {
            let (name, timeout) = match token.split_once('|') {
                Some((name, secs)) => {
                    let secs = secs.trim_end_matches('*');
                    match secs.parse::<u32>() {
                        Ok(s) if s > 0 => (name, Some(s)),
                        _ => {
                            return Err(GenerateError::BadTimeout {
                                line,
                                token: token.to_string(),
                            });
                        }
                    }
                }
                None => (token.trim_end_matches('*'), None),
            };
            if !is_action_name(name) {
                return Err(GenerateError::BadName {
                    line,
                    name: name.to_string(),
                });
            }
            steps.push(PlanStep {
                action: name.to_string(),
                timeout,
            });
        }
    }
    Ok(steps)
}

/// Reads a linear plan in either form: an IPC plan when its first line that
/// is not blank or a comment starts with `(` (or a temporal planner's `t:`),
/// PNPgen's line otherwise.
pub fn parse_linear_plan(text: &str) -> Result<Vec<PlanStep>, GenerateError> {
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with(';') && !l.starts_with('#'));
    let ipc = first.is_some_and(|l| {
        l.starts_with('(')
            || l.split_once(':')
                .is_some_and(|(t, rest)| t.trim().parse::<f64>().is_ok() && rest.trim_start().starts_with('('))
    });
    if ipc {
        parse_ipc_plan(text)
    } else {
        parse_pnpgen_line(text)
    }
}
