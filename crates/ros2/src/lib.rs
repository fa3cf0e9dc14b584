//! A ROS 2 robot as a learnpnp world over rmw_zenoh's wire format, with no
//! ROS 2 installed: key expressions, liveliness tokens, attachments, CDR and
//! RIHS01 type hashes as ros2/rmw_zenoh's `docs/design.md` describes them
//! ([`keys`], [`cdr`], [`types`]).

pub mod cdr;
pub mod keys;
pub mod mapping;
pub mod node;
pub mod plan_state;
pub mod types;
pub mod world;
