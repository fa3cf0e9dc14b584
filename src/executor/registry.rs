//! Instantiating actions and sub-plans by name.

use std::collections::HashMap;
use std::sync::Arc;

use super::Action;
use super::PlanKey;
use crate::plan::Plan;

type Factory<W> = Box<dyn Fn(&str) -> Box<dyn Action<W>> + Send + Sync>;

/// How one name is executed.
pub(crate) enum Entry<'a, W> {
    /// A primitive action: its declared internal conditions and its factory.
    Primitive {
        /// Declared condition names, in index order.
        declared: &'a [String],
        /// Builds an instance for a full action name.
        factory: &'a Factory<W>,
    },
    /// A sub-plan and its key.
    SubPlan(PlanKey, &'a Arc<Plan>),
}

struct Primitive<W> {
    declared: Vec<String>,
    factory: Factory<W>,
}

/// What a registry provides under one name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RegisteredKind {
    /// An action of exactly this name.
    Action,
    /// Every action named `name` or `name_<parameters>`.
    Family,
    /// A sub-plan.
    SubPlan,
}

/// One name a registry provides, for listings and error messages.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Registered {
    /// The name (a family's prefix).
    pub name: String,
    /// What it is.
    pub(crate) kind: RegisteredKind,
    /// The internal conditions its guards may test (`name.cond`), besides
    /// `finished` and `failed`.
    pub(crate) conditions: Vec<String>,
}

impl Registered {
    /// How a plan names it: `name`, `name_<parameters>` for a family.
    pub fn pattern(&self) -> String {
        match self.kind {
            RegisteredKind::Family => format!("{}_<parameters>", self.name),
            _ => self.name.clone(),
        }
    }
}

/// Maps action names to factories and sub-plans.
///
/// A name resolves, in order: an exact registration; a family registered for
/// its prefix (`goto` matches `goto_3_4`, whose parameters the factory parses);
/// the same two without the `robot#` agent prefix; a registered sub-plan of
/// that name.
pub struct Registry<W> {
    actions: HashMap<String, Primitive<W>>,
    families: Vec<(String, Primitive<W>)>,
    plans: Vec<Arc<Plan>>,
}

impl<W> Default for Registry<W> {
    fn default() -> Self {
        Registry {
            actions: HashMap::new(),
            families: Vec::new(),
            plans: Vec::new(),
        }
    }
}

impl<W> Registry<W> {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Registers action `name`, declaring its internal conditions, built by `factory`
    /// (which receives the full name as written in the plan).
    pub fn action<F, A>(&mut self, name: &str, declared: &[&str], factory: F) -> &mut Self
    where
        F: Fn(&str) -> A + Send + Sync + 'static,
        A: Action<W> + 'static,
    {
        let declared = declared.iter().map(|s| s.to_string()).collect();
        self.actions.insert(
            name.to_string(),
            Primitive {
                declared,
                factory: Box::new(move |n| Box::new(factory(n))),
            },
        );
        self
    }

    /// Registers every action named `prefix` or `prefix_<parameters>`.
    pub fn family<F, A>(&mut self, prefix: &str, declared: &[&str], factory: F) -> &mut Self
    where
        F: Fn(&str) -> A + Send + Sync + 'static,
        A: Action<W> + 'static,
    {
        let declared = declared.iter().map(|s| s.to_string()).collect();
        self.families.push((
            prefix.to_string(),
            Primitive {
                declared,
                factory: Box::new(move |n| Box::new(factory(n))),
            },
        ));
        self
    }

    /// Registers `plan` as a sub-plan called by its name; returns its key.
    pub fn sub_plan(&mut self, plan: Arc<Plan>) -> PlanKey {
        self.plans.push(plan);
        PlanKey(self.plans.len() as u16)
    }

    /// The sub-plans in key order (key 1 first).
    pub fn sub_plans(&self) -> &[Arc<Plan>] {
        &self.plans
    }

    /// Every name provided: actions and families by name, then sub-plans in key order.
    pub(crate) fn entries(&self) -> Vec<Registered> {
        let mut out: Vec<Registered> = self
            .actions
            .iter()
            .map(|(name, p)| (name, p, RegisteredKind::Action))
            .chain(self.families.iter().map(|(name, p)| (name, p, RegisteredKind::Family)))
            .map(|(name, p, kind)| Registered {
                name: name.clone(),
                kind,
                conditions: p.declared.clone(),
            })
            .collect();
        out.sort_by(|a, b| a.name.cmp(&b.name));
        out.extend(self.plans.iter().map(|p| Registered {
            name: p.name().to_string(),
            kind: RegisteredKind::SubPlan,
            conditions: Vec::new(),
        }));
        out
    }

    /// The error for `action`, used by `plan`, that nothing here provides: it
    /// lists what is registered.
    pub(crate) fn unknown_action(&self, plan: &str, action: &str) -> super::ExecError {
        let names: Vec<String> = self.entries().into_iter().map(|e| e.pattern()).collect();
        super::ExecError::UnknownAction {
            plan: plan.to_string(),
            action: action.to_string(),
            registered: if names.is_empty() {
                "nothing".to_string()
            } else {
                names.join(", ")
            },
        }
    }

    fn primitive(&self, name: &str) -> Option<&Primitive<W>> {
        self.actions.get(name).or_else(|| {
            self.families
                .iter()
                .find(|(prefix, _)| {
                    name == prefix || name.strip_prefix(prefix.as_str()).is_some_and(|r| r.starts_with('_'))
                })
                .map(|(_, p)| p)
        })
    }

    /// How `name` is executed, if anything provides it.
    pub(crate) fn resolve(&self, name: &str) -> Option<Entry<'_, W>> {
        let base = name.split_once('#').map(|(_, b)| b);
        let primitive = self.primitive(name).or_else(|| base.and_then(|b| self.primitive(b)));
        if let Some(p) = primitive {
            return Some(Entry::Primitive {
                declared: &p.declared,
                factory: &p.factory,
            });
        }
        self.plans
            .iter()
            .position(|p| p.name() == name || Some(p.name()) == base)
            .map(|i| Entry::SubPlan(PlanKey(i as u16 + 1), &self.plans[i]))
    }
}
