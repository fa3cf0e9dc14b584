//! A ROS 2 robot as a learnpnp world over rmw_zenoh's wire format, with no
//! ROS 2 installed: key expressions, liveliness tokens, attachments, CDR and
//! RIHS01 type hashes as ros2/rmw_zenoh's `docs/design.md` describes them
//! ([`keys`], [`cdr`], [`types`]); ROS 2 nodes on a Zenoh session
//! ([`node`], opened by the secure link's code: [`link`]); the mapping file
//! ([`mapping`]) and the world it makes ([`world`], served by the
//! `learnpnp-ros2-world` binary); the plan's state as ROS 2 topics
//! ([`plan_state`]), republished from the agents' live feed ([`feed`]).
//! The guide's page `docs/guide/src/ros2.md` is the user's guide.

/// CDR as rmw_zenoh sends it.
pub mod cdr;
/// The agents' live feed, republished as the plan's state.
pub mod feed;
/// rmw_zenoh's key expressions, liveliness tokens and attachments.
pub mod keys;
/// The world's Zenoh session.
pub mod link;
/// The mapping file: a ROS 2 robot as a learnpnp world.
pub mod mapping;
/// A ROS 2 node on a Zenoh session, as rmw_zenoh makes one.
pub mod node;
/// The plan's state as ROS 2 topics.
pub mod plan_state;
/// ROS 2 interface types, their type hashes and CDR encoding.
pub mod types;
/// The world a mapping file makes of a ROS 2 robot.
pub mod world;
