//! Whether guards can hold together, every atom taken as a free boolean.

use crate::condition::{AtomRef, Condition};

/// The most distinct atoms whose assignments are enumerated; guards mentioning
/// more are assumed jointly satisfiable.
pub const MAX_GUARD_ATOMS: usize = 12;

/// Whether some truth assignment of the atoms makes every guard true. Atoms,
/// internal conditions such as `A.finished` included, are independent booleans.
/// Beyond [`MAX_GUARD_ATOMS`] distinct atoms the answer is `true` (assumed).
pub fn jointly_satisfiable(guards: &[&Condition]) -> bool {
    let mut atoms: Vec<AtomRef> = Vec::new();
    for guard in guards {
        for atom in guard.atoms() {
            if !atoms.contains(&atom) {
                atoms.push(atom);
            }
        }
    }
    if atoms.len() > MAX_GUARD_ATOMS {
        return true;
    }
    (0u32..1 << atoms.len()).any(|bits| {
        let value = |atom: AtomRef| {
            atoms
                .iter()
                .position(|&a| a == atom)
                .is_some_and(|i| bits & (1 << i) != 0)
        };
        guards.iter().all(|g| g.eval(&value))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::condition::AtomId;

    fn atom(i: u32) -> Condition {
        Condition::Atom(AtomRef::Fact(AtomId(i)))
    }

    fn not(c: Condition) -> Condition {
        Condition::Not(Box::new(c))
    }

    #[test]
    fn complementary_guards_exclude_each_other() {
        assert!(!jointly_satisfiable(&[&atom(0), &not(atom(0))]));
        assert!(jointly_satisfiable(&[&atom(0), &atom(1)]));
        assert!(jointly_satisfiable(&[&Condition::True, &Condition::True]));
        let both = Condition::And(vec![atom(0), atom(1)].into_boxed_slice());
        let neither = Condition::Not(Box::new(Condition::Or(vec![atom(0), atom(1)].into_boxed_slice())));
        assert!(!jointly_satisfiable(&[&both, &neither]));
        assert!(!jointly_satisfiable(&[&both, &not(atom(1))]));
    }

    #[test]
    fn too_many_atoms_are_assumed_satisfiable() {
        let many: Vec<Condition> = (0..=MAX_GUARD_ATOMS as u32).map(atom).collect();
        let all = Condition::And(many.into_boxed_slice());
        let none = not(atom(0));
        assert!(jointly_satisfiable(&[&all, &none]));
    }
}
