//! Conditions compiled to atom ids.

use super::{AtomId, Expr};

/// What a compiled atom refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AtomRef {
    /// A fact asked of the knowledge base.
    Fact(AtomId),
    /// An internal condition of an action (`A.finished`, `A.failed`, or one it
    /// declares): an index into the owning plan's internal-condition table.
    Internal(u32),
}

/// A condition ready for the hot path: atoms are ids, evaluation allocates nothing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Condition {
    /// Always true.
    True,
    /// One atom.
    Atom(AtomRef),
    /// Negation.
    Not(Box<Condition>),
    /// All must hold.
    And(Box<[Condition]>),
    /// One must hold.
    Or(Box<[Condition]>),
}

impl Condition {
    /// Compiles `expr`, resolving each atom name with `resolve`.
    pub(crate) fn compile<E>(expr: &Expr, resolve: &mut impl FnMut(&str) -> Result<AtomRef, E>) -> Result<Self, E> {
        Ok(match expr {
            Expr::True => Condition::True,
            Expr::Atom(a) => Condition::Atom(resolve(a)?),
            Expr::Not(e) => Condition::Not(Box::new(Self::compile(e, resolve)?)),
            Expr::And(es) => Condition::And(es.iter().map(|e| Self::compile(e, resolve)).collect::<Result<_, E>>()?),
            Expr::Or(es) => Condition::Or(es.iter().map(|e| Self::compile(e, resolve)).collect::<Result<_, E>>()?),
        })
    }

    /// Evaluates with `atom` answering each atom.
    #[inline]
    pub fn eval(&self, atom: &impl Fn(AtomRef) -> bool) -> bool {
        match self {
            Condition::True => true,
            Condition::Atom(a) => atom(*a),
            Condition::Not(c) => !c.eval(atom),
            Condition::And(cs) => cs.iter().all(|c| c.eval(atom)),
            Condition::Or(cs) => cs.iter().any(|c| c.eval(atom)),
        }
    }

    /// Whether this is the always-true condition.
    pub fn is_true(&self) -> bool {
        matches!(self, Condition::True)
    }

    /// Every atom referenced, in order.
    pub fn atoms(&self) -> Vec<AtomRef> {
        let mut out = Vec::new();
        self.collect(&mut out);
        out
    }

    fn collect(&self, out: &mut Vec<AtomRef>) {
        match self {
            Condition::True => {}
            Condition::Atom(a) => out.push(*a),
            Condition::Not(c) => c.collect(out),
            Condition::And(cs) | Condition::Or(cs) => cs.iter().for_each(|c| c.collect(out)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::parse_condition;
    use super::*;

    #[test]
    fn compiles_and_evaluates() {
        let expr = parse_condition("or (and a b) (not c)").unwrap();
        let names = ["a", "b", "c"];
        let cond = Condition::compile(&expr, &mut |n: &str| -> Result<AtomRef, ()> {
            Ok(AtomRef::Fact(
                AtomId(names.iter().position(|x| *x == n).unwrap() as u32),
            ))
        })
        .unwrap();
        let truth = |bits: [bool; 3]| move |a: AtomRef| matches!(a, AtomRef::Fact(id) if bits[id.index()]);
        assert!(cond.eval(&truth([true, true, true])));
        assert!(!cond.eval(&truth([true, false, true])));
        assert!(cond.eval(&truth([false, false, false])));
    }

    #[test]
    fn resolver_errors_propagate() {
        let expr = parse_condition("and a zz").unwrap();
        let r = Condition::compile(&expr, &mut |n: &str| {
            if n == "a" {
                Ok(AtomRef::Internal(0))
            } else {
                Err(n.to_string())
            }
        });
        assert_eq!(r, Err("zz".to_string()));
    }
}
