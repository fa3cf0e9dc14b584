//! The keepers' notes on the log board: what a plan-driven keeper does and
//! chose, encoded as one message and decoded back.

use std::fmt::Write as _;

use serde::Serialize;

use super::*;

/// One option of a keeper's choice: the transitions that lead to it, its
/// learned value and how often that value was updated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OptionNote {
    /// The labels of the transitions that lead to this option (`Pass1.start`).
    pub name: String,
    /// Its value when the keeper chose (negative infinity: no estimate yet).
    pub value: f64,
    /// Updates of that value so far.
    pub visits: u64,
}

/// A keeper's last choice at a choice point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChoiceNote {
    /// The cycle of the choice.
    pub cycle: u32,
    /// Where the plan stood: the labels of its marked places.
    pub at: String,
    /// The options offered.
    pub options: Vec<OptionNote>,
    /// The index of the option taken.
    pub chosen: usize,
}

/// What a plan-driven keeper is doing: its current action and its last choice.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KeeperNote {
    /// The keeper's uniform number (1 to 3).
    pub keeper: u8,
    /// The actions whose execution places are marked (`Hold`, `Pass1`...).
    pub action: String,
    /// The last choice made this episode, if any.
    pub choice: Option<ChoiceNote>,
}

/// Escapes the characters that separate a note's fields, and the quote and
/// line breaks a message may not contain, as `%XX`.
fn escape_field(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '%' | '|' | ';' | '=' | '"' | '\n' | '\r' | ')' | '(' => {
                let _ = write!(out, "%{:02X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out
}

/// Reverses [`escape_field`]; `None` on a malformed escape.
fn unescape_field(text: &str) -> Option<String> {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars();
    while let Some(c) = chars.next() {
        if c == '%' {
            let hex: String = chars.by_ref().take(2).collect();
            let code = u32::from_str_radix(&hex, 16).ok()?;
            out.push(char::from_u32(code)?);
        } else {
            out.push(c);
        }
    }
    Some(out)
}

/// A value with at most four decimals (`-inf` for none).
fn value_text(value: f64) -> String {
    if value == f64::NEG_INFINITY {
        "-inf".to_string()
    } else {
        num(value, 4)
    }
}

impl KeeperNote {
    /// The note as the text of a log message:
    /// `learnpnp keeper=1|action=Hold|cycle=12|at=...|chosen=0|option=Hold.start;14.2;31|...`.
    pub(crate) fn to_message(&self) -> String {
        let mut text = format!(
            "{NOTE_PREFIX}keeper={}|action={}",
            self.keeper,
            escape_field(&self.action)
        );
        if let Some(c) = &self.choice {
            let _ = write!(
                text,
                "|cycle={}|at={}|chosen={}",
                c.cycle,
                escape_field(&c.at),
                c.chosen
            );
            for o in &c.options {
                let _ = write!(
                    text,
                    "|option={};{};{}",
                    escape_field(&o.name),
                    value_text(o.value),
                    o.visits
                );
            }
        }
        text
    }

    /// Reads a message written by [`KeeperNote::to_message`]; `Ok(None)` for
    /// any other message, `Err` with the offending field for a malformed note.
    pub(crate) fn from_message(text: &str) -> Result<Option<KeeperNote>, String> {
        let Some(body) = text.strip_prefix(NOTE_PREFIX) else {
            return Ok(None);
        };
        let mut keeper = None;
        let mut action = String::new();
        let mut cycle = None;
        let mut at = String::new();
        let mut chosen = None;
        let mut options = Vec::new();
        for field in body.split('|') {
            let (key, value) = field.split_once('=').ok_or_else(|| field.to_string())?;
            let text = || unescape_field(value).ok_or_else(|| field.to_string());
            match key {
                "keeper" => keeper = Some(value.parse::<u8>().map_err(|_| field.to_string())?),
                "action" => action = text()?,
                "cycle" => cycle = Some(value.parse::<u32>().map_err(|_| field.to_string())?),
                "at" => at = text()?,
                "chosen" => chosen = Some(value.parse::<usize>().map_err(|_| field.to_string())?),
                "option" => {
                    let mut parts = value.split(';');
                    let (Some(name), Some(v), Some(n), None) = (parts.next(), parts.next(), parts.next(), parts.next())
                    else {
                        return Err(field.to_string());
                    };
                    options.push(OptionNote {
                        name: unescape_field(name).ok_or_else(|| field.to_string())?,
                        value: v.parse::<f64>().map_err(|_| field.to_string())?,
                        visits: n.parse::<u64>().map_err(|_| field.to_string())?,
                    });
                }
                _ => {}
            }
        }
        let keeper = keeper.ok_or_else(|| "keeper".to_string())?;
        let choice = match (cycle, chosen) {
            (Some(cycle), Some(chosen)) if chosen < options.len() => Some(ChoiceNote {
                cycle,
                at,
                options,
                chosen,
            }),
            (None, None) if options.is_empty() => None,
            _ => return Err("chosen".to_string()),
        };
        Ok(Some(KeeperNote { keeper, action, choice }))
    }
}
