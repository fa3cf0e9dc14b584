//! Plan files in PNML: reading and writing [`PetriNet`](crate::net::PetriNet)s.
//!
//! Two dialects are understood. [`Dialect::Jarp`](crate::pnml::Dialect::Jarp) is what the JARP editor of the
//! Petri Net Plans library writes (and what that library reads): nodes directly
//! in the `net`, values in `<value>` (markings possibly as `Default,1`), the plan
//! name in a comment `PLAN NAME: ...`. [`Dialect::Standard`](crate::pnml::Dialect::Standard) is ISO/IEC 15909-2
//! place/transition PNML as pm4py and other tools write it: nodes in (possibly
//! nested) `page`s, values in `<text>`, the name in `net/name`. [`parse`](crate::pnml::parse) detects
//! the dialect; [`write`](fn@crate::pnml::write) takes it as an argument. Labels are opaque strings here.
//!
//! `parse(&write(net, d), _)` equals `net` for both dialects (see [`write`](fn@crate::pnml::write) for
//! the few strings XML cannot carry).

mod dialect;
mod error;
mod file;
mod read;
mod write;

pub use dialect::Dialect;
pub use error::{PnmlError, PnmlFileError, UnknownDialect};
pub use file::{read_file, write_file};
pub use read::{MAX_NESTING, parse};
pub use write::write;
