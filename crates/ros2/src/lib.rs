//! A ROS 2 robot as a learnpnp world over rmw_zenoh's wire format, with no
//! ROS 2 installed: key expressions, liveliness tokens, attachments, CDR and
//! RIHS01 type hashes as ros2/rmw_zenoh's `docs/design.md` describes them
//! ([`keys`], [`cdr`], [`types`]); ROS 2 nodes on a Zenoh session
//! ([`node`], opened by the secure link's code: [`link`]); the mapping file
//! ([`mapping`]) and the world it makes ([`world`], served by the
//! `learnpnp-ros2-world` binary); the plan's state as ROS 2 topics
//! ([`plan_state`]), republished from the agents' live feed ([`feed`]).
//! `docs/ROS2.md` is the user's guide.

pub mod cdr;
pub mod feed;
pub mod keys;
pub mod link;
pub mod mapping;
pub mod node;
pub mod plan_state;
pub mod types;
pub mod world;
