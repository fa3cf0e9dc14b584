//! Guard conditions: the prefix grammar of the PNP library, parsed once and
//! compiled so the executor evaluates atom ids, never strings.

mod compiled;
mod knowledge;
mod parse;

pub use compiled::{AtomRef, Condition};
pub use knowledge::{AtomId, AtomTable, BitKnowledgeBase, KnowledgeBase};
pub use parse::{ConditionError, Expr, PREFIX_FORM, parse_condition};
