//! PNPgen's execution rules: `*if* COND *during* ACTION *do* RECOVERY`.
//!
//! A rule applies to every occurrence of ACTION in the plan: an action whose
//! name is ACTION, or whose name's first `_`-separated word is (PNPgen matches
//! `goto` to `goto_printer`). Each occurrence gets an interrupt
//! `ACTION.interrupt [COND]` from its execution place into the recovery
//! branch: the RECOVERY actions in sequence, then its last word:
//!
//! - `skip_action`: on to the place after the action;
//! - `restart_action`: back to the place before it;
//! - `restart_plan`: back to the plan's initial place;
//! - `fail_plan`: into the plan's fail place;
//! - `goal`: into its goal place.
//!
//! The condition `action_failed` is the action's failure: the branch leaves
//! by `ACTION.fail` instead of an interrupt. Recovery actions get no rules
//! (PNPgen's choice). A timed action's interrupt also takes its wait's token.

use super::{GenerateError, GeneratedPlan, PlanStep, linear};
use crate::condition::{AtomTable, parse_condition};

/// How a recovery branch ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Recovery {
    /// On to the place after the action.
    SkipAction,
    /// Back to the place before it.
    RestartAction,
    /// Back to the plan's initial place.
    RestartPlan,
    /// Into the plan's fail place.
    FailPlan,
    /// Into the plan's goal place.
    Goal,
}

impl Recovery {
    /// The word ending a rule.
    fn from_word(word: &str) -> Option<Self> {
        Some(match word {
            "skip_action" => Recovery::SkipAction,
            "restart_action" => Recovery::RestartAction,
            "restart_plan" => Recovery::RestartPlan,
            "fail_plan" => Recovery::FailPlan,
            "goal" => Recovery::Goal,
            _ => return None,
        })
    }

    /// The word, as a transition's name.
    fn word(self) -> &'static str {
        match self {
            Recovery::SkipAction => "skip_action",
            Recovery::RestartAction => "restart_action",
            Recovery::RestartPlan => "restart_plan",
            Recovery::FailPlan => "fail_plan",
            Recovery::Goal => "goal",
        }
    }
}

/// One execution rule.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExecutionRule {
    /// 1-based line of its file (what errors name).
    pub line: usize,
    /// The condition, a guard body (`and personhere (not closetotarget)`), or
    /// `action_failed`.
    pub condition: String,
    /// The action it watches.
    pub action: String,
    /// The recovery actions, in order.
    pub recovery: Vec<PlanStep>,
    /// How the recovery ends.
    pub then: Recovery,
}

/// Reads execution rules, one a line; `#` starts a comment line.
pub fn parse_rules(text: &str) -> Result<Vec<ExecutionRule>, GenerateError> {
    let mut rules = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let trimmed = raw.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let bad = |expected: String| GenerateError::BadRule {
            line,
            text: trimmed.to_string(),
            expected,
        };
        let form = "a rule reads *if* CONDITION *during* ACTION *do* RECOVERY".to_string();
        let rest = trimmed.strip_prefix("*if*").ok_or_else(|| bad(form.clone()))?;
        let (condition, rest) = rest.split_once("*during*").ok_or_else(|| bad(form.clone()))?;
        let (action, recovery) = rest.split_once("*do*").ok_or_else(|| bad(form.clone()))?;
        let (condition, action) = (condition.trim(), action.trim());
        if condition.is_empty() {
            return Err(bad("the condition is empty".to_string()));
        }
        if condition != "action_failed" {
            parse_condition(condition).map_err(|e| bad(format!("the condition does not read: {e}")))?;
        }
        if !linear::is_action_name(action) {
            return Err(bad(format!("'{action}' cannot name an action")));
        }
        let mut words: Vec<&str> = recovery
            .split(|c: char| c == ';' || c.is_whitespace())
            .filter(|w| !w.is_empty())
            .collect();
        let last = words.pop().ok_or_else(|| {
            bad(
                "the recovery is empty: it ends in skip_action, restart_action, restart_plan, fail_plan or goal"
                    .to_string(),
            )
        })?;
        let then = Recovery::from_word(last).ok_or_else(|| {
            bad(format!(
                "the recovery ends in '{last}', not in skip_action, restart_action, restart_plan, fail_plan or goal"
            ))
        })?;
        let recovery = linear::parse_pnpgen_line(&words.join(";")).map_err(|e| bad(format!("the recovery: {e}")))?;
        rules.push(ExecutionRule {
            line,
            condition: condition.to_string(),
            action: action.to_string(),
            recovery,
            then,
        });
    }
    Ok(rules)
}

/// Whether a rule for `rule_action` applies to the action `name`.
fn applies(rule_action: &str, name: &str) -> bool {
    name == rule_action || name.split('_').next() == Some(rule_action)
}

impl GeneratedPlan {
    /// Adds every rule to every occurrence of its action. With `atoms`, the
    /// atoms of each condition (but internal conditions `A.cond`) must be
    /// among them. A rule whose action the plan lacks is an error naming it.
    pub fn apply_rules(&mut self, rules: &[ExecutionRule], atoms: Option<&AtomTable>) -> Result<(), GenerateError> {
        for rule in rules {
            if let Some(table) = atoms
                && rule.condition != "action_failed"
            {
                let expr = parse_condition(&rule.condition).map_err(|e| GenerateError::BadRule {
                    line: rule.line,
                    text: rule.condition.clone(),
                    expected: e.to_string(),
                })?;
                if let Some(atom) = expr
                    .atoms()
                    .into_iter()
                    .find(|a| !a.contains('.') && table.get(a).is_none())
                {
                    return Err(GenerateError::UnknownRuleAtom {
                        line: rule.line,
                        atom: atom.to_string(),
                        known: table.names().collect::<Vec<_>>().join(", "),
                    });
                }
            }
            let sites: Vec<_> = self
                .sites
                .iter()
                .filter(|s| applies(&rule.action, &s.name))
                .cloned()
                .collect();
            if sites.is_empty() {
                return Err(GenerateError::UnknownRuleAction {
                    line: rule.line,
                    action: rule.action.clone(),
                    known: self.actions().join(", "),
                });
            }
            for site in sites {
                let start = self.builder.place("");
                let mut inputs = vec![(site.exec, 1)];
                inputs.extend(site.wait_exec.map(|w| (w, 1)));
                let label = if rule.condition == "action_failed" {
                    format!("{}.fail", site.name)
                } else {
                    format!("{}.interrupt [{}]", site.name, rule.condition)
                };
                self.builder.transition(label, &inputs, &[(start, 1)]);
                let target = match rule.then {
                    Recovery::SkipAction => site.after,
                    Recovery::RestartAction => site.before,
                    Recovery::RestartPlan => self.init,
                    Recovery::FailPlan => self.fail_place(),
                    Recovery::Goal => self.goal,
                };
                if rule.recovery.is_empty() {
                    self.builder.transition(rule.then.word(), &[(start, 1)], &[(target, 1)]);
                } else {
                    let end = self.builder.place("");
                    self.chain(start, &rule.recovery, end, false);
                    self.builder.transition(rule.then.word(), &[(end, 1)], &[(target, 1)]);
                }
            }
        }
        Ok(())
    }
}
