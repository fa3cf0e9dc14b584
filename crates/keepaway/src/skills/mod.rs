//! The keepaway framework's skills, as pure functions of a
//! [`PlayerView`](crate::view::PlayerView) and the configuration
//! returning a [`Command`](crate::command::Command); passing and
//! intercepting keep a small explicit memory ([`pass::PassState`](crate::skills::pass::PassState),
//! [`intercept::InterceptMemory`](crate::skills::intercept::InterceptMemory)).
//!
//! The numbers follow the framework (Stone, Kuhlmann; built on UvA Trilearn's
//! `BasicPlayer`), collected in [`crate::params::SkillParams`]; each skill
//! documents where it deviates.

/// Who gets to the ball first.
pub mod fastest;
/// Getting open for a pass.
pub mod get_open;
/// Holding the ball.
pub mod hold;
/// Intercepting the ball.
pub mod intercept;
/// Ball-kicking skills.
pub mod kick;
/// Turning and moving.
pub(crate) mod movement;
/// Passing.
pub mod pass;
/// The framework's world-model predictions.
pub mod predict;

pub use get_open::{get_open, get_open_from, go_to_support_point};
pub use hold::hold_ball;
pub use intercept::{InterceptMemory, intercept};
pub use movement::{go_to_point, turn_to_ball};
pub use pass::PassState;
