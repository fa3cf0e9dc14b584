//! Showing a schema's process: a text listing (`learnpnp schema`), Graphviz DOT
//! (`--dot`), and structural checks (`learnpnp check` on a schema).

use std::fmt::Write as _;

use super::construct::{DecisionProcess, MachineProcess, ProcessTransition};

/// A plan state with its actions, as the thesis names action states: `approach {GoToBall, TrackBall}`.
fn action_state(mp: &MachineProcess, state: usize) -> String {
    let s = &mp.machine().states()[state];
    let mut text = format!("{} {{{}}}", s.name, s.actions.join(", "));
    match s.kind {
        super::StateKind::Ordinary => {}
        super::StateKind::Final => text.push_str(" final"),
        super::StateKind::Failure => text.push_str(" final, failed"),
    }
    text
}

fn event_name(mp: &MachineProcess, state: usize, group: usize) -> &str {
    mp.groups(state)[group].event.as_deref().unwrap_or("(empty event)")
}

/// `n thing` or `n things`.
fn count(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

fn machine_summary(out: &mut String, index: usize, mp: &MachineProcess) {
    let c = mp.counts();
    let role = if index == 0 { "root, " } else { "" };
    let _ = writeln!(out, "machine {} ({role}plan key {index})", mp.name());
    let _ = writeln!(
        out,
        "  |S| = {}, |S_c| = {}, |S_sp| = {}",
        count(c.action_states, "action state"),
        count(c.constituent_states, "constituent state"),
        c.action_states + c.constituent_states
    );
    let _ = writeln!(
        out,
        "  {} ({}), {}, {} ({})",
        count(c.events + c.loops, "event transition"),
        count(c.loops, "loop"),
        count(c.plan_actions, "plan-action"),
        count(c.choice_states, "choice state"),
        count(c.options, "option")
    );
}

/// The constructed process of every machine: states, transitions, choice states and counts.
pub fn describe(process: &DecisionProcess) -> String {
    let mut out = String::new();
    let machines = process.machines();
    let _ = writeln!(
        out,
        "schema {}: {} machine{}",
        machines[0].name(),
        machines.len(),
        if machines.len() == 1 { "" } else { "s" }
    );
    for (i, mp) in machines.iter().enumerate() {
        out.push('\n');
        machine_summary(&mut out, i, mp);
        let _ = writeln!(out, "\n  action states (S)");
        for s in 0..mp.machine().states().len() {
            let initial = if s == mp.machine().initial() { "  (initial)" } else { "" };
            let _ = writeln!(out, "    {}{initial}", action_state(mp, s));
        }
        let transitions = mp.transitions();
        let _ = writeln!(out, "\n  events (time-extended, carry the reward)");
        for t in &transitions {
            match *t {
                ProcessTransition::Event { state, group, to } => {
                    let from = &mp.machine().states()[state].name;
                    let _ = writeln!(out, "    {from} --{}--> {}", event_name(mp, state, group), mp.label(to));
                }
                ProcessTransition::Loop { state, group } => {
                    let from = &mp.machine().states()[state].name;
                    let _ = writeln!(
                        out,
                        "    {from} --{}--> {from}   (no condition holds)",
                        event_name(mp, state, group)
                    );
                }
                ProcessTransition::PlanAction { .. } => {}
            }
        }
        let _ = writeln!(out, "\n  plan-actions (zero time, deterministic)");
        for t in &transitions {
            if let ProcessTransition::PlanAction { from, action } = *t {
                let _ = writeln!(out, "    {} => {}", mp.label(from), action_state(mp, action.target));
            }
        }
        let _ = writeln!(out, "\n  choice states (a learner decides)");
        let mut any = false;
        for c in mp.choice_states() {
            any = true;
            let options: Vec<&str> = c
                .plan_actions
                .iter()
                .map(|a| mp.machine().states()[a.target].name.as_str())
                .collect();
            let _ = writeln!(out, "    {}: {}", mp.label(c.state), options.join(" | "));
        }
        if !any {
            let _ = writeln!(out, "    none: the machine is deterministic");
        }
    }
    out
}

fn dot_escape(s: &str) -> String {
    s.replace('\\', "\\\\").replace('"', "\\\"")
}

/// The process as Graphviz DOT: action states as boxes (final ones doubled),
/// constituent states as ellipses (choice states filled), events as solid
/// edges, plan-actions as dashed ones.
pub fn to_dot(process: &DecisionProcess) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "// learnpnp schema process: boxes are action states (S), ellipses constituent states (S_c);\n\
         // solid edges are events (time-extended, carrying the reward), dashed edges plan-actions (zero time);\n\
         // filled ellipses are choice states."
    );
    let _ = writeln!(
        out,
        "digraph \"{}\" {{\n  rankdir=LR;",
        dot_escape(process.machines()[0].name())
    );
    for (m, mp) in process.machines().iter().enumerate() {
        let _ = writeln!(out, "  subgraph \"cluster_{m}\" {{");
        let _ = writeln!(out, "    label=\"{}\";", dot_escape(mp.name()));
        let node = |id: usize| format!("m{m}s{id}");
        // An edge between two states of this machine, with more attributes before its label.
        let edge = |out: &mut String, from: usize, to: usize, attributes: &str, label: &str| {
            let _ = writeln!(
                out,
                "    {} -> {} [{attributes}label=\"{}\"];",
                node(from),
                node(to),
                dot_escape(label)
            );
        };
        for (s, state) in mp.machine().states().iter().enumerate() {
            let shape = if state.kind.is_final() {
                "box, peripheries=2"
            } else {
                "box"
            };
            let bold = if s == mp.machine().initial() {
                ", style=bold"
            } else {
                ""
            };
            let _ = writeln!(
                out,
                "    {} [shape={shape}{bold}, label=\"{}\"];",
                node(s),
                dot_escape(&action_state(mp, s))
            );
        }
        for t in mp.transitions() {
            match t {
                ProcessTransition::Event { state, group, to } => {
                    let choice = mp.choice_states().any(|c| c.state == to);
                    let style = if choice {
                        ", style=filled, fillcolor=lightgoldenrod"
                    } else {
                        ""
                    };
                    let _ = writeln!(
                        out,
                        "    {} [shape=ellipse{style}, label=\"{}\"];",
                        node(to),
                        dot_escape(mp.label(to))
                    );
                    edge(&mut out, state, to, "", event_name(mp, state, group));
                }
                ProcessTransition::Loop { state, group } => {
                    let label = format!("{} (none holds)", event_name(mp, state, group));
                    edge(&mut out, state, state, "", &label);
                }
                ProcessTransition::PlanAction { from, action } => {
                    let actions = &mp.machine().states()[action.target].actions;
                    let label = format!("{{{}}}", actions.join(", "));
                    edge(&mut out, from, action.target, "style=dashed, ", &label);
                }
            }
        }
        let _ = writeln!(out, "  }}");
    }
    out.push_str("}\n");
    out
}

/// Plan states reachable from the initial one, every event and condition taken as possible.
fn reachable(mp: &MachineProcess) -> Vec<bool> {
    let n = mp.machine().states().len();
    let mut seen = vec![false; n];
    let mut stack = vec![mp.machine().initial()];
    seen[mp.machine().initial()] = true;
    while let Some(s) = stack.pop() {
        for c in mp.groups(s).iter().flat_map(|g| &g.constituents) {
            for a in &c.plan_actions {
                if !seen[a.target] {
                    seen[a.target] = true;
                    stack.push(a.target);
                }
            }
        }
    }
    seen
}

/// Plan states from which a final state can be reached.
fn can_finish(mp: &MachineProcess) -> Vec<bool> {
    let states = mp.machine().states();
    let mut ok: Vec<bool> = states.iter().map(|s| s.kind.is_final()).collect();
    loop {
        let mut changed = false;
        for s in 0..states.len() {
            if ok[s] {
                continue;
            }
            let reaches = mp
                .groups(s)
                .iter()
                .flat_map(|g| &g.constituents)
                .flat_map(|c| &c.plan_actions)
                .any(|a| ok[a.target]);
            if reaches {
                ok[s] = true;
                changed = true;
            }
        }
        if !changed {
            return ok;
        }
    }
}

/// Structural checks of every machine, every event and condition taken as
/// possible: each plan state is reachable; no reachable non-final state runs
/// nothing and has no edge (it would never be left); where a machine has final states,
/// one can be reached from every reachable state. Returns the report and
/// whether every check passed. A machine no other machine calls is noted.
pub fn check_report(process: &DecisionProcess) -> (String, bool) {
    fn verdict(out: &mut String, passed: &mut bool, name: &str, bad: &[&str], what: &str) {
        if bad.is_empty() {
            let _ = writeln!(out, "  PASS {name}");
        } else {
            *passed = false;
            let _ = writeln!(out, "  FAIL {name}: {what}: {}", bad.join(", "));
        }
    }
    let mut out = String::new();
    let mut passed = true;
    let machines = process.machines();
    for (i, mp) in machines.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        machine_summary(&mut out, i, mp);
        let states = mp.machine().states();
        let seen = reachable(mp);
        let names = |pick: &dyn Fn(usize) -> bool| -> Vec<&str> {
            (0..states.len())
                .filter(|&s| pick(s))
                .map(|s| states[s].name.as_str())
                .collect()
        };
        let never_left = |s: usize| seen[s] && !states[s].kind.is_final() && mp.groups(s).is_empty();
        let unreachable = names(&|s| !seen[s]);
        verdict(
            &mut out,
            &mut passed,
            "reachable",
            &unreachable,
            "never entered from the initial state",
        );
        let dead = names(&|s| never_left(s) && states[s].actions.is_empty());
        let what = "no edge leaves these states and nothing runs in them";
        verdict(&mut out, &mut passed, "no dead states", &dead, what);
        let endless = names(&|s| never_left(s) && !states[s].actions.is_empty());
        if !endless.is_empty() {
            let _ = writeln!(
                out,
                "  note: no edge leaves {}: their actions run until the caller or the episode ends them",
                endless.join(", ")
            );
        }
        if states.iter().any(|s| s.kind.is_final()) {
            let finish = can_finish(mp);
            let stuck = names(&|s| seen[s] && !finish[s]);
            let what = "no final state can be reached from these states";
            verdict(&mut out, &mut passed, "effective", &stuck, what);
        } else {
            let _ = writeln!(
                out,
                "  note: no final state, the machine runs until its caller or the episode ends it"
            );
        }
        if i > 0
            && !machines
                .iter()
                .any(|m| m.actions().iter().any(|a| a.machine == Some(i)))
        {
            let _ = writeln!(out, "  note: no machine calls it");
        }
    }
    let _ = writeln!(out, "\nresult: {}", if passed { "passed" } else { "failed" });
    (out, passed)
}

/// The failed checks of a [`check_report`], one line each (without `FAIL`).
pub fn check_failures(report: &str) -> Vec<String> {
    report
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("FAIL "))
        .map(str::to_string)
        .collect()
}
