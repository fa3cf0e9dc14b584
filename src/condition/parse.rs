//! The prefix condition grammar.
//!
//! ```text
//! cond  := '(' inner ')' | ATOM
//! inner := and cond cond+ | or cond cond+ | not cond | ATOM | cond
//! ATOM  := [a-zA-Z][-@a-zA-Z0-9._#{,}<>"+^/]*
//! ```
//! Guard text is wrapped in parentheses before parsing, so `not a` and
//! `and a b c` are accepted as written inside `[...]`.

/// A parsed condition, atoms still as names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Expr {
    /// Always true (the empty guard `[]`).
    True,
    /// A named atom: a knowledge-base fact or an internal condition `A.cond`.
    Atom(String),
    /// Negation.
    Not(Box<Expr>),
    /// Conjunction of at least two conditions.
    And(Vec<Expr>),
    /// Disjunction of at least two conditions.
    Or(Vec<Expr>),
}

impl Expr {
    /// Every atom name, in order of appearance.
    pub fn atoms(&self) -> Vec<&str> {
        let mut out = Vec::new();
        self.collect_atoms(&mut out);
        out
    }

    fn collect_atoms<'a>(&'a self, out: &mut Vec<&'a str>) {
        match self {
            Expr::True => {}
            Expr::Atom(a) => out.push(a),
            Expr::Not(e) => e.collect_atoms(out),
            Expr::And(es) | Expr::Or(es) => es.iter().for_each(|e| e.collect_atoms(out)),
        }
    }

    /// The condition in the prefix syntax, as a guard body (no brackets).
    pub fn to_guard_text(&self) -> String {
        match self {
            Expr::True => String::new(),
            Expr::Atom(a) => a.clone(),
            Expr::Not(e) => format!("not {}", e.nested()),
            Expr::And(es) => format!("and {}", join_nested(es)),
            Expr::Or(es) => format!("or {}", join_nested(es)),
        }
    }

    fn nested(&self) -> String {
        match self {
            Expr::Atom(a) => a.clone(),
            Expr::True => "()".to_string(),
            other => format!("({})", other.to_guard_text()),
        }
    }
}

fn join_nested(es: &[Expr]) -> String {
    es.iter().map(Expr::nested).collect::<Vec<_>>().join(" ")
}

/// How conditions are written, shown with every error of one that does not parse.
pub const PREFIX_FORM: &str = "conditions are written in prefix form, operator first: [and a b], [or a b], [not a], nested in parentheses: [or a (and b c)]";

/// A condition that does not parse: what was wrong, the offending token, and
/// how to write it ([`ConditionError::hint`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct ConditionError {
    /// What was expected.
    pub message: String,
    /// The token where parsing failed (`<end>` when the text ran out).
    pub token: String,
    /// Byte offset of that token in `text`.
    pub offset: usize,
    /// The condition text as written.
    pub text: String,
}

/// `message at 'token' (offset n of 'text'); hint`.
impl std::fmt::Display for ConditionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} at '{}' (offset {} of '{}'); {}",
            self.message,
            self.token,
            self.offset,
            self.text,
            self.hint()
        )
    }
}

impl ConditionError {
    /// How to write the condition: for an operator written between its
    /// operands (`a and b`, `a && b`), that it goes first, with the condition
    /// rewritten where it is one operator between atoms; otherwise
    /// [`PREFIX_FORM`].
    pub fn hint(&self) -> String {
        let Some(op) = infix_operator(&self.token) else {
            return PREFIX_FORM.to_string();
        };
        // The operator is infix when it follows an operand: an atom or a ')'.
        let before = self.text.get(..self.offset).unwrap_or("").trim_end();
        let after_operand = before.ends_with(')')
            || before
                .rsplit(|c: char| c.is_ascii_whitespace() || c == '(')
                .next()
                .is_some_and(|word| is_atom(word) && is_keyword(word).is_none());
        if !after_operand {
            return PREFIX_FORM.to_string();
        }
        let written = &self.token;
        let (prefix, infix) = match prefix_rewrite(&self.text) {
            Some(rewritten) => (rewritten, self.text.trim().to_string()),
            None => (format!("{op} a b"), format!("a {written} b")),
        };
        if is_keyword(written).is_some() {
            format!("'{written}' is an operator, written first: [{prefix}], not [{infix}]")
        } else {
            format!("the operator is '{op}', written first: [{prefix}], not [{infix}]")
        }
    }
}

/// The binary operator `token` means when written between operands: `and`
/// or `or` (as keywords, or as C's `&&`, `&`, `||`, `|`).
fn infix_operator(token: &str) -> Option<&'static str> {
    match token {
        "&&" | "&" => Some("and"),
        "||" | "|" => Some("or"),
        _ => is_keyword(token).filter(|&op| op != "not"),
    }
}

/// `a and b and c` (atoms joined by one infix operator) as `and a b c`.
fn prefix_rewrite(text: &str) -> Option<String> {
    let words: Vec<&str> = text.split_whitespace().collect();
    if words.len() < 3 || words.len().is_multiple_of(2) {
        return None;
    }
    let op = infix_operator(words[1])?;
    let same_operator = words.iter().skip(1).step_by(2).all(|w| infix_operator(w) == Some(op));
    let atoms: Vec<&str> = words.iter().step_by(2).copied().collect();
    let all_atoms = atoms.iter().all(|a| is_atom(a) && is_keyword(a).is_none());
    (same_operator && all_atoms).then(|| format!("{op} {}", atoms.join(" ")))
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Token<'a> {
    Open,
    Close,
    Word(&'a str),
    End,
}

struct Lexer<'a> {
    text: &'a str,
    pos: usize,
}

impl<'a> Lexer<'a> {
    fn next(&mut self) -> (Token<'a>, usize) {
        let bytes = self.text.as_bytes();
        while self.pos < bytes.len() && bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let start = self.pos;
        match bytes.get(self.pos) {
            None => (Token::End, start),
            Some(b'(') => {
                self.pos += 1;
                (Token::Open, start)
            }
            Some(b')') => {
                self.pos += 1;
                (Token::Close, start)
            }
            Some(_) => {
                while self.pos < bytes.len()
                    && !matches!(bytes[self.pos], b'(' | b')')
                    && !bytes[self.pos].is_ascii_whitespace()
                {
                    self.pos += 1;
                }
                (Token::Word(&self.text[start..self.pos]), start)
            }
        }
    }
}

struct Parser<'a> {
    lexer: Lexer<'a>,
    peeked: Option<(Token<'a>, usize)>,
    original: &'a str,
    shift: usize,
}

fn is_keyword(word: &str) -> Option<&'static str> {
    match word {
        "and" | "AND" => Some("and"),
        "or" | "OR" => Some("or"),
        "not" | "NOT" => Some("not"),
        _ => None,
    }
}

fn is_atom(word: &str) -> bool {
    let mut chars = word.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || "-@._#{,}<>\"+^/".contains(c))
}

impl<'a> Parser<'a> {
    fn peek(&mut self) -> (Token<'a>, usize) {
        if self.peeked.is_none() {
            self.peeked = Some(self.lexer.next());
        }
        self.peeked.unwrap_or((Token::End, 0))
    }

    fn bump(&mut self) -> (Token<'a>, usize) {
        let t = self.peek();
        self.peeked = None;
        t
    }

    fn error(&self, message: &str, token: Token<'_>, offset: usize) -> ConditionError {
        // The ')' wrapping the text is not the user's: there the text ended.
        let wrapper_close = token == Token::Close && offset + 1 == self.lexer.text.len();
        let token = if wrapper_close { Token::End } else { token };
        let token = match token {
            Token::Open => "(".to_string(),
            Token::Close => ")".to_string(),
            Token::Word(w) => w.to_string(),
            Token::End => "<end>".to_string(),
        };
        ConditionError {
            message: message.to_string(),
            token,
            offset: offset.saturating_sub(self.shift).min(self.original.len()),
            text: self.original.to_string(),
        }
    }

    fn atom(&self, word: &'a str, offset: usize) -> Result<Expr, ConditionError> {
        if is_keyword(word).is_some() {
            return Err(self.error("operator used as an atom", Token::Word(word), offset));
        }
        if !is_atom(word) {
            return Err(self.error("malformed atom", Token::Word(word), offset));
        }
        Ok(Expr::Atom(word.to_string()))
    }

    fn cond(&mut self, depth: usize) -> Result<Expr, ConditionError> {
        if depth > 64 {
            let (t, o) = self.peek();
            return Err(self.error("condition nested too deeply", t, o));
        }
        match self.bump() {
            (Token::Word(w), o) => self.atom(w, o),
            (Token::Open, _) => {
                let inner = self.inner(depth + 1)?;
                match self.bump() {
                    (Token::Close, _) => Ok(inner),
                    (t, o) => Err(self.error("expected ')'", t, o)),
                }
            }
            (t, o) => Err(self.error("expected an atom or '('", t, o)),
        }
    }

    fn inner(&mut self, depth: usize) -> Result<Expr, ConditionError> {
        match self.peek() {
            (Token::Close, _) => Ok(Expr::True),
            (Token::Word(w), o) => match is_keyword(w) {
                Some(op) => {
                    self.bump();
                    let mut operands = Vec::new();
                    while !matches!(self.peek().0, Token::Close | Token::End) {
                        operands.push(self.cond(depth + 1)?);
                    }
                    let (t, end) = self.peek();
                    match (op, operands.len()) {
                        ("not", 1) => Ok(Expr::Not(Box::new(operands.remove(0)))),
                        ("not", _) => Err(self.error("'not' takes exactly one operand", Token::Word(w), o)),
                        (_, n) if n < 2 => Err(self.error(&format!("'{op}' needs at least two operands"), t, end)),
                        ("and", _) => Ok(Expr::And(operands)),
                        _ => Ok(Expr::Or(operands)),
                    }
                }
                None => {
                    self.bump();
                    self.atom(w, o)
                }
            },
            _ => self.cond(depth + 1),
        }
    }
}

/// Parses a guard body (the text between `[` and `]`); empty text is `True`.
pub fn parse_condition(text: &str) -> Result<Expr, ConditionError> {
    if text.trim().is_empty() {
        return Ok(Expr::True);
    }
    // A ')' without its '(' would close the wrapping below: report it here.
    let mut depth = 0usize;
    for (offset, byte) in text.bytes().enumerate() {
        match byte {
            b'(' => depth += 1,
            b')' if depth == 0 => {
                return Err(ConditionError {
                    message: "')' without a matching '('".to_string(),
                    token: ")".to_string(),
                    offset,
                    text: text.to_string(),
                });
            }
            b')' => depth -= 1,
            _ => {}
        }
    }
    let wrapped = format!("({text})");
    let mut parser = Parser {
        lexer: Lexer { text: &wrapped, pos: 0 },
        peeked: None,
        original: text,
        shift: 1,
    };
    let expr = parser.cond(0)?;
    match parser.bump() {
        (Token::End, _) => Ok(expr),
        (t, o) => Err(parser.error("unexpected text after the condition", t, o)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn atom(a: &str) -> Expr {
        Expr::Atom(a.into())
    }

    #[test]
    fn parses_the_grammar() {
        assert_eq!(parse_condition("").unwrap(), Expr::True);
        assert_eq!(parse_condition("ballSeen").unwrap(), atom("ballSeen"));
        assert_eq!(parse_condition("not a").unwrap(), Expr::Not(Box::new(atom("a"))));
        assert_eq!(
            parse_condition("and a b c").unwrap(),
            Expr::And(vec![atom("a"), atom("b"), atom("c")])
        );
        assert_eq!(
            parse_condition("OR (not a) (AND b c.finished)").unwrap(),
            Expr::Or(vec![
                Expr::Not(Box::new(atom("a"))),
                Expr::And(vec![atom("b"), atom("c.finished")])
            ])
        );
        assert_eq!(parse_condition("(a)").unwrap(), atom("a"));
        assert_eq!(parse_condition("robot#near{1,2}").unwrap(), atom("robot#near{1,2}"));
    }

    #[test]
    fn errors_name_the_token() {
        let e = parse_condition("and a").unwrap_err();
        assert!(e.message.contains("two operands"), "{e}");
        let e = parse_condition("not a b").unwrap_err();
        assert_eq!(e.token, "not");
        let e = parse_condition("a b").unwrap_err();
        assert_eq!(e.token, "b");
        assert_eq!(e.offset, 2);
        let e = parse_condition("(a").unwrap_err();
        assert_eq!(e.token, "<end>");
        let e = parse_condition("and").unwrap_err();
        assert_eq!((e.token.as_str(), e.offset), ("<end>", 3));
        let e = parse_condition("3x").unwrap_err();
        assert_eq!(e.token, "3x");
        let e = parse_condition("a)").unwrap_err();
        assert_eq!((e.token.as_str(), e.offset), (")", 1));
        let e = parse_condition("(a))b").unwrap_err();
        assert_eq!((e.token.as_str(), e.offset), (")", 3));
        let e = parse_condition("not and").unwrap_err();
        assert_eq!(e.token, "and");
    }

    #[test]
    fn infix_operators_are_recognised_only_after_an_operand() {
        let hint = |text: &str| parse_condition(text).unwrap_err().hint();
        assert_eq!(
            hint("a and b"),
            "'and' is an operator, written first: [and a b], not [a and b]"
        );
        assert_eq!(
            hint("a OR b or c"),
            "'OR' is an operator, written first: [or a b c], not [a OR b or c]"
        );
        assert_eq!(
            hint("x && y"),
            "the operator is 'and', written first: [and x y], not [x && y]"
        );
        assert_eq!(
            hint("(not a) || b"),
            "the operator is 'or', written first: [or a b], not [a || b]"
        );
        assert_eq!(
            hint("a and b or c"),
            "'and' is an operator, written first: [and a b], not [a and b]"
        );
        // Not after an operand, or not an infix operator: the grammar in general.
        for text in ["not and", "or and a b", "a b", "3x", "a not b", "and a"] {
            assert_eq!(hint(text), PREFIX_FORM, "{text}");
        }
    }

    #[test]
    fn deep_nesting_is_refused_not_overflowed() {
        let text = format!("{}a{}", "(not ".repeat(500), ")".repeat(500));
        assert!(parse_condition(&text).is_err());
    }

    #[test]
    fn guard_text_round_trips() {
        for text in ["a", "not a", "and a b", "or (not a) (and b c) d", "not (or a b)"] {
            let e = parse_condition(text).unwrap();
            assert_eq!(parse_condition(&e.to_guard_text()).unwrap(), e, "{text}");
        }
    }
}
