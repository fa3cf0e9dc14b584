//! The mapping file: a ROS 2 robot's topics, services and actions as a
//! learnpnp world's atoms, fluents, reward, episode end and actions.
//!
//! TOML (the `toml` crate), not YAML: TOML has one way to write each value
//! and a maintained Rust parser with line-and-column errors, while the YAML
//! crate in our tree (serde_yaml) is deprecated; a ROS 2 user reads TOML's
//! `[[atom]]` tables as easily as a launch file's YAML. The guide's `docs/guide/src/ros2.md` is the
//! reference.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use serde::Deserialize;
use thiserror::Error;

use crate::types::{Elem, Registry, Shape, TypeError, Value};

/// A mapping file that cannot be used.
#[derive(Debug, Error)]
pub enum MappingError {
    /// The file cannot be read.
    #[error("{file}: {error}")]
    Read {
        /// The file.
        file: PathBuf,
        /// The error.
        error: std::io::Error,
    },
    /// Not TOML of the mapping's form.
    #[error("{file}: {error}")]
    Syntax {
        /// The file.
        file: PathBuf,
        /// The parser's message (line, column and token).
        error: String,
    },
    /// An entry that does not make sense.
    #[error("{file}: {entry}: '{token}': {why}")]
    Entry {
        /// The file.
        file: PathBuf,
        /// The entry (`[[atom]] 'at_end'`).
        entry: String,
        /// The offending token.
        token: String,
        /// What is wrong.
        why: String,
    },
}

fn default_domain() -> u32 {
    0
}
fn default_node() -> String {
    "learnpnp_world".into()
}
fn default_namespace() -> String {
    "/".into()
}
fn default_field() -> String {
    "data".into()
}
fn default_timeout() -> u64 {
    5000
}

/// `[ros]`: the node the world is.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RosSection {
    /// ROS_DOMAIN_ID.
    #[serde(default = "default_domain")]
    pub domain: u32,
    /// The world's node name.
    #[serde(default = "default_node")]
    pub node: String,
    /// Its namespace.
    #[serde(default = "default_namespace")]
    pub namespace: String,
}

impl Default for RosSection {
    fn default() -> Self {
        RosSection {
            domain: default_domain(),
            node: default_node(),
            namespace: default_namespace(),
        }
    }
}

fn default_publish() -> bool {
    true
}
fn default_plan_namespace() -> String {
    "/learnpnp".into()
}

/// `[plan_state]`: the agents' plan state as ROS 2 topics, as PNPros
/// published it (`pnp/currentActivePlaces`, `pnp/runningActions`,
/// `pnp/choices`, agent `n`'s under `{namespace}/agent{n}`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanStateSection {
    /// Whether the world republishes the agents' plan state.
    #[serde(default = "default_publish")]
    pub publish: bool,
    /// The namespace the agents' namespaces are in (absolute).
    #[serde(default = "default_plan_namespace")]
    pub namespace: String,
}

impl Default for PlanStateSection {
    fn default() -> Self {
        PlanStateSection {
            publish: default_publish(),
            namespace: default_plan_namespace(),
        }
    }
}

/// `[zenoh]`: where the Zenoh router (rmw_zenohd or zenohd) is.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ZenohSection {
    /// Endpoints to connect to (`tcp/127.0.0.1:7447`; `quic/...` with `tls`).
    #[serde(default)]
    pub connect: Vec<String>,
    /// Endpoints to listen on (the world is then the router).
    #[serde(default)]
    pub listen: Vec<String>,
    /// A directory with the secure link's `ca.pem`, `cert.pem` and `key.pem`
    /// (made by `learnpnp-supervisor link-certs`): mutual TLS over QUIC.
    pub tls: Option<PathBuf>,
}

/// A `.msg`, `.srv` or `.action` file beyond the built-in types.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Interface {
    /// Its full name (`corridor_msgs/action/Move`).
    pub name: String,
    /// Its file, relative to the mapping file.
    pub file: PathBuf,
}

/// A value derived from a field that is a message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Derived {
    /// The yaw of a quaternion (`geometry_msgs/msg/Quaternion`, or any
    /// message with numeric `x`, `y`, `z`, `w`): the rotation about z in
    /// radians, `atan2(2 (w z + x y), 1 - 2 (y² + z²))`, in (-π, π]
    /// (0: facing +x, π/2: facing +y, ±π: facing -x; REP 103's z-up frames).
    Yaw,
}

impl Derived {
    /// The derived value of `v` (the field the source names), if it has
    /// what it is derived from.
    fn of(self, v: &Value) -> Option<f64> {
        match self {
            Derived::Yaw => {
                let c = |n: &str| v.get(n).and_then(Value::as_f64);
                let (x, y, z, w) = (c("x")?, c("y")?, c("z")?, c("w")?);
                Some((2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z)))
            }
        }
    }

    /// The fields it is derived from.
    fn inputs(self) -> &'static [&'static str] {
        match self {
            Derived::Yaw => &["x", "y", "z", "w"],
        }
    }
}

/// Where a value comes from: a field of a topic's messages, or of a service's response.
#[derive(Debug, Clone)]
pub(crate) struct Source {
    /// A topic (the latest message counts).
    pub topic: Option<String>,
    /// A service (called with its default request after each step).
    pub service: Option<String>,
    /// The message or service type (`std_msgs/msg/Bool`).
    pub type_name: String,
    /// The field, dotted for nested ones (`range`, `header.stamp.sec`).
    pub field: String,
    /// A value derived from the field (a message), instead of the field itself.
    pub derive: Option<Derived>,
}

impl Source {
    /// The source's value in `message` (a message or response): its field,
    /// or the value derived from it.
    pub(crate) fn read(&self, message: &Value) -> Option<Value> {
        let v = message.path(&self.field)?;
        match self.derive {
            None => Some(v.clone()),
            Some(d) => d.of(v).map(Value::Float),
        }
    }

    /// The source's value in `message` as a number.
    pub(crate) fn number(&self, message: &Value) -> Option<f64> {
        self.read(message).as_ref().and_then(Value::as_f64)
    }
}

/// An entry as written: a source, and for conditions one of `equals`, `below`, `above`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEntry {
    #[serde(default)]
    name: String,
    topic: Option<String>,
    service: Option<String>,
    #[serde(rename = "type")]
    type_name: String,
    #[serde(default = "default_field")]
    field: String,
    derive: Option<Derived>,
    equals: Option<toml::Value>,
    below: Option<f64>,
    above: Option<f64>,
    between: Option<[f64; 2]>,
}

impl RawEntry {
    fn source(&self) -> Source {
        Source {
            topic: self.topic.clone(),
            service: self.service.clone(),
            type_name: self.type_name.clone(),
            field: self.field.clone(),
            derive: self.derive,
        }
    }
}

/// A condition on a field: one of `equals`, `below`, `above`, `between`.
#[derive(Debug, Clone, Deserialize)]
#[serde(from = "RawEntry")]
pub struct Condition {
    /// Its name (an atom's).
    pub name: String,
    /// Where its value comes from.
    pub(crate) source: Source,
    /// True when the field equals this (a boolean, integer, float or string).
    pub equals: Option<toml::Value>,
    /// True when the field is below this.
    pub below: Option<f64>,
    /// True when the field is above this.
    pub above: Option<f64>,
    /// True when the field is within these bounds (both included; on a
    /// yaw, `[a, b]` with `a > b` is the arc from `a` through ±π to `b`).
    pub between: Option<[f64; 2]>,
}

impl From<RawEntry> for Condition {
    fn from(r: RawEntry) -> Self {
        Condition {
            source: r.source(),
            name: r.name,
            equals: r.equals,
            below: r.below,
            above: r.above,
            between: r.between,
        }
    }
}

/// A numeric field (a fluent, the reward).
#[derive(Debug, Clone, Deserialize)]
#[serde(try_from = "RawEntry")]
pub struct Reading {
    /// Its name (a fluent's; empty for the reward).
    pub name: String,
    /// Where its value comes from.
    pub(crate) source: Source,
}

impl TryFrom<RawEntry> for Reading {
    type Error = String;
    fn try_from(r: RawEntry) -> Result<Self, String> {
        if r.equals.is_some() || r.below.is_some() || r.above.is_some() || r.between.is_some() {
            return Err(format!(
                "'{}': a reading takes no condition (equals, below, above, between)",
                r.name
            ));
        }
        Ok(Reading {
            source: r.source(),
            name: r.name,
        })
    }
}

/// A plan action: a message on a topic, or a goal of a ROS 2 action.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActionMap {
    /// The plan's action name.
    pub name: String,
    /// A topic to publish `message` on.
    pub topic: Option<String>,
    /// A ROS 2 action to send `goal` to.
    pub action: Option<String>,
    /// The message or action type.
    #[serde(rename = "type")]
    pub type_name: String,
    /// The message (for a topic) or goal (for an action), by field.
    #[serde(default)]
    pub message: toml::Table,
    /// The numeric field the world writes each command's sequence number
    /// into (needed on a topic's command when `[answer]` has `sequence`).
    pub sequence: Option<String>,
}

/// `[answer]`: the robot's answer to each command and reset (lock-step).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Answer {
    /// The topic the robot publishes on after each command, once its state is published.
    pub topic: String,
    /// Its type.
    #[serde(rename = "type")]
    pub type_name: String,
    /// The numeric field of the answer that carries the sequence number of
    /// the command it answers: an answer to another command is refused and
    /// counted (none: any message on the topic is the answer).
    pub sequence: Option<String>,
}

/// `[reset]`: the service starting an episode.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResetCall {
    /// The service.
    pub service: String,
    /// Its type (`std_srvs/srv/Empty`).
    #[serde(rename = "type")]
    pub type_name: String,
    /// The request, by field (unset fields are zero).
    #[serde(default)]
    pub request: toml::Table,
}

/// The mapping file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mapping {
    /// The world's node.
    #[serde(default)]
    pub ros: RosSection,
    /// The Zenoh session.
    pub zenoh: ZenohSection,
    /// The plan's state as ROS 2 topics.
    #[serde(default)]
    pub plan_state: PlanStateSection,
    /// Interface files.
    #[serde(default)]
    pub interfaces: Vec<Interface>,
    /// Atoms.
    #[serde(default, rename = "atom")]
    pub atoms: Vec<Condition>,
    /// Fluents.
    #[serde(default, rename = "fluent")]
    pub(crate) fluents: Vec<Reading>,
    /// Actions.
    #[serde(default, rename = "action")]
    pub actions: Vec<ActionMap>,
    /// The reward: a topic's messages summed over a step, or a service's answer after it.
    pub reward: Option<Reading>,
    /// A reward added at every step.
    #[serde(default)]
    pub step_reward: f64,
    /// The episode's end.
    pub end: Option<Condition>,
    /// Steps after which an episode is cut short.
    pub max_steps: Option<u32>,
    /// The reset service.
    pub reset: Option<ResetCall>,
    /// The robot's answer.
    pub answer: Option<Answer>,
    /// How long to wait for the robot's answer, a result or a reply (ms).
    #[serde(default = "default_timeout")]
    pub timeout_ms: u64,
}

/// A loaded mapping: the file's contents and the types it uses.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The mapping.
    pub mapping: Mapping,
    /// The types, built-in and from `[[interfaces]]`.
    pub registry: Registry,
    /// The file's directory (relative paths start there).
    pub dir: PathBuf,
}

/// Reads and checks a mapping file.
pub fn load(file: &Path) -> Result<Loaded, MappingError> {
    let text = std::fs::read_to_string(file).map_err(|error| MappingError::Read {
        file: file.to_path_buf(),
        error,
    })?;
    parse(file, &text)
}

/// Parses and checks mapping text read from `file`.
pub(crate) fn parse(file: &Path, text: &str) -> Result<Loaded, MappingError> {
    let mapping: Mapping = toml::from_str(text).map_err(|e| MappingError::Syntax {
        file: file.to_path_buf(),
        error: e.to_string(),
    })?;
    let dir = file.parent().map(Path::to_path_buf).unwrap_or_default();
    let entry = |entry: String, token: &str, why: String| MappingError::Entry {
        file: file.to_path_buf(),
        entry,
        token: token.to_string(),
        why,
    };
    let mut registry = Registry::new();
    for i in &mapping.interfaces {
        let path = dir.join(&i.file);
        let text = std::fs::read_to_string(&path).map_err(|e| {
            entry(
                format!("[[interfaces]] '{}'", i.name),
                &i.file.display().to_string(),
                e.to_string(),
            )
        })?;
        registry
            .add_interface(&i.name, &text)
            .map_err(|e| entry(format!("[[interfaces]] '{}'", i.name), &i.name, e.to_string()))?;
    }
    let check = Checker {
        registry: &registry,
        entry: &entry,
    };
    let mut names = BTreeSet::new();
    for a in &mapping.atoms {
        let what = format!("[[atom]] '{}'", a.name);
        check.name(&what, &a.name, &mut names)?;
        check.condition(&what, a)?;
    }
    for f in &mapping.fluents {
        let what = format!("[[fluent]] '{}'", f.name);
        check.name(&what, &f.name, &mut names)?;
        check.numeric(&what, &f.source)?;
    }
    let mut actions = BTreeSet::new();
    // A topic or ROS 2 action has one type, whichever plan actions use it.
    let mut types: BTreeMap<&str, &str> = BTreeMap::new();
    for a in &mapping.actions {
        let what = format!("[[action]] '{}'", a.name);
        check.name(&what, &a.name, &mut actions)?;
        check.action(&what, a)?;
        if let Some(target) = a.topic.as_deref().or(a.action.as_deref())
            && let Some(other) = types.insert(target, &a.type_name).filter(|t| *t != a.type_name)
        {
            return Err(entry(
                what,
                &a.type_name,
                format!("'{target}' is already mapped with the type {other}"),
            ));
        }
    }
    if mapping.actions.is_empty() {
        return Err(entry(
            "[[action]]".into(),
            "",
            "a world needs at least one action".into(),
        ));
    }
    if let Some(r) = &mapping.reward {
        check.numeric("[reward]", &r.source)?;
    }
    if let Some(e) = &mapping.end {
        check.condition("[end]", e)?;
    }
    if let Some(r) = &mapping.reset {
        check.service_type("[reset]", &r.type_name)?;
        let (request, _) = registry
            .service(&r.type_name)
            .map_err(|e| entry("[reset]".into(), &r.type_name, e.to_string()))?;
        check.message("[reset]", request, &r.request)?;
    }
    if let Some(a) = &mapping.answer {
        check.msg_type("[answer]", &a.type_name)?;
        if let Some(field) = &a.sequence {
            check.sequence_field("[answer]", &a.type_name, field)?;
        }
    }
    for a in &mapping.actions {
        let what = format!("[[action]] '{}'", a.name);
        match (&a.sequence, mapping.answer.as_ref().and_then(|a| a.sequence.as_ref())) {
            (Some(field), Some(_)) => {
                let message_type = match &a.topic {
                    Some(_) => a.type_name.clone(),
                    None => format!("{}_Goal", a.type_name),
                };
                check.sequence_field(&what, &message_type, field)?;
            }
            (Some(field), None) => {
                return Err(entry(
                    what,
                    field,
                    "a command's sequence number is matched by [answer]'s `sequence`: give it there".into(),
                ));
            }
            (None, Some(_)) if a.topic.is_some() => {
                return Err(entry(
                    what,
                    "sequence",
                    "[answer] matches answers by `sequence`: name the command's field the world writes it into".into(),
                ));
            }
            (None, _) => {}
        }
    }
    let namespace = &mapping.plan_state.namespace;
    if !namespace.starts_with('/')
        || namespace.len() > 1 && namespace.ends_with('/')
        || namespace.contains("//")
        || !namespace
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '/')
    {
        return Err(entry(
            "[plan_state]".into(),
            namespace,
            "a namespace is absolute, of letters, digits, '_' and '/' (\"/learnpnp\")".into(),
        ));
    }
    if mapping.zenoh.connect.is_empty() && mapping.zenoh.listen.is_empty() {
        return Err(entry(
            "[zenoh]".into(),
            "connect",
            "give the router's endpoint (connect = [\"tcp/127.0.0.1:7447\"])".into(),
        ));
    }
    Ok(Loaded { mapping, registry, dir })
}

struct Checker<'a, F: Fn(String, &str, String) -> MappingError> {
    registry: &'a Registry,
    entry: &'a F,
}

/// What a field path ends on.
enum FieldKind {
    Bool,
    Number,
    Text,
}

impl<F: Fn(String, &str, String) -> MappingError> Checker<'_, F> {
    fn err(&self, what: &str, token: &str, why: impl Into<String>) -> MappingError {
        (self.entry)(what.to_string(), token, why.into())
    }

    fn name(&self, what: &str, name: &str, seen: &mut BTreeSet<String>) -> Result<(), MappingError> {
        if name.is_empty() || name.chars().any(char::is_whitespace) {
            return Err(self.err(what, name, "give a name without spaces"));
        }
        if !seen.insert(name.to_string()) {
            return Err(self.err(what, name, "named twice"));
        }
        Ok(())
    }

    fn msg_type(&self, what: &str, t: &str) -> Result<(), MappingError> {
        self.registry
            .msg(t)
            .map(drop)
            .map_err(|e| self.err(what, t, e.to_string()))
    }

    fn service_type(&self, what: &str, t: &str) -> Result<(), MappingError> {
        self.registry
            .service(t)
            .map(drop)
            .map_err(|e| self.err(what, t, e.to_string()))
    }

    /// The message type a source's field is read from.
    fn source_type(&self, what: &str, s: &Source) -> Result<String, MappingError> {
        match (&s.topic, &s.service) {
            (Some(_), None) => {
                self.msg_type(what, &s.type_name)?;
                Ok(s.type_name.clone())
            }
            (None, Some(_)) => {
                self.service_type(what, &s.type_name)?;
                let (_, resp) = self
                    .registry
                    .service(&s.type_name)
                    .map_err(|e| self.err(what, &s.type_name, e.to_string()))?;
                Ok(resp.to_string())
            }
            _ => Err(self.err(what, "topic", "give either topic or service")),
        }
    }

    /// Checks that `field` of `message_type` is a number (a sequence number's field).
    fn sequence_field(&self, what: &str, message_type: &str, field: &str) -> Result<(), MappingError> {
        let source = Source {
            topic: Some(String::new()),
            service: None,
            type_name: message_type.to_string(),
            field: field.to_string(),
            derive: None,
        };
        match self.field(what, &source)? {
            FieldKind::Number => Ok(()),
            _ => Err(self.err(what, field, "a sequence number's field is numeric")),
        }
    }

    fn field(&self, what: &str, s: &Source) -> Result<FieldKind, MappingError> {
        let mut t = self.source_type(what, s)?;
        let parts: Vec<&str> = s.field.split('.').collect();
        for (i, part) in parts.iter().enumerate() {
            let def = self
                .registry
                .msg(&t)
                .map_err(|e: TypeError| self.err(what, &t, e.to_string()))?;
            let Some(f) = def.fields.iter().find(|f| f.name == *part) else {
                let known: Vec<&str> = def.fields.iter().map(|f| f.name.as_str()).collect();
                return Err(self.err(
                    what,
                    &s.field,
                    format!("{t} has no field '{part}' (its fields: {})", known.join(", ")),
                ));
            };
            if f.shape != Shape::Single {
                return Err(self.err(what, &s.field, format!("'{part}' is an array or sequence")));
            }
            match &f.elem {
                Elem::Nested(n) if i + 1 < parts.len() => t = n.clone(),
                Elem::Nested(n) => {
                    return match s.derive {
                        Some(d) => self.derived_from(what, s, n, d),
                        None => Err(self.err(what, &s.field, format!("'{part}' is a {n}, name one of its fields"))),
                    };
                }
                Elem::Prim(_) if i + 1 < parts.len() => {
                    return Err(self.err(what, &s.field, format!("'{part}' has no fields")));
                }
                Elem::Prim(_) if s.derive.is_some() => {
                    return Err(self.err(what, &s.field, format!("'{part}' is not a message to derive from")));
                }
                Elem::Prim(p) => {
                    return Ok(match p {
                        crate::types::Prim::Bool => FieldKind::Bool,
                        crate::types::Prim::String | crate::types::Prim::BoundedString(_) => FieldKind::Text,
                        _ => FieldKind::Number,
                    });
                }
            }
        }
        Err(self.err(what, &s.field, "empty field"))
    }

    /// A value derived from message type `t` (the field `s` names): a
    /// number, if `t` has the numeric fields it is derived from.
    fn derived_from(&self, what: &str, s: &Source, t: &str, d: Derived) -> Result<FieldKind, MappingError> {
        let def = self.registry.msg(t).map_err(|e| self.err(what, t, e.to_string()))?;
        for input in d.inputs() {
            let numeric = def.fields.iter().any(|f| {
                f.name == *input
                    && f.shape == Shape::Single
                    && matches!(&f.elem, Elem::Prim(p) if !matches!(p, crate::types::Prim::Bool | crate::types::Prim::String | crate::types::Prim::BoundedString(_)))
            });
            if !numeric {
                return Err(self.err(
                    what,
                    &s.field,
                    format!(
                        "{d:?} is derived from a message with numeric {} ({t} has no numeric '{input}')",
                        d.inputs().join(", ")
                    ),
                ));
            }
        }
        Ok(FieldKind::Number)
    }

    fn numeric(&self, what: &str, s: &Source) -> Result<(), MappingError> {
        match self.field(what, s)? {
            FieldKind::Text => Err(self.err(what, &s.field, "a string is not a number")),
            _ => Ok(()),
        }
    }

    fn condition(&self, what: &str, c: &Condition) -> Result<(), MappingError> {
        let kind = self.field(what, &c.source)?;
        if let Some([lo, hi]) = c.between {
            if c.equals.is_some() || c.below.is_some() || c.above.is_some() {
                return Err(self.err(what, "between", "give exactly one of equals, below, above, between"));
            }
            let arc = c.source.derive == Some(Derived::Yaw) && lo > hi;
            if !(lo <= hi || arc) || lo.is_nan() || hi.is_nan() {
                return Err(self.err(
                    what,
                    "between",
                    format!(
                        "[{lo}, {hi}]: the lower bound comes first (on a yaw, [a, b] with a > b is the arc through ±π)"
                    ),
                ));
            }
            return match kind {
                FieldKind::Number => Ok(()),
                _ => Err(self.err(what, &c.source.field, "between needs a numeric field")),
            };
        }
        match (&c.equals, c.below, c.above) {
            (Some(v), None, None) => {
                let fits = matches!(
                    (&kind, v),
                    (FieldKind::Bool, toml::Value::Boolean(_))
                        | (FieldKind::Number, toml::Value::Integer(_) | toml::Value::Float(_))
                        | (FieldKind::Text, toml::Value::String(_))
                );
                if fits {
                    Ok(())
                } else {
                    Err(self.err(what, &v.to_string(), format!("cannot equal field '{}'", c.source.field)))
                }
            }
            (None, Some(_), None) | (None, None, Some(_)) => match kind {
                FieldKind::Number => Ok(()),
                _ => Err(self.err(what, &c.source.field, "below and above need a numeric field")),
            },
            _ => Err(self.err(what, "equals", "give exactly one of equals, below, above, between")),
        }
    }

    fn action(&self, what: &str, a: &ActionMap) -> Result<(), MappingError> {
        let message_type = match (&a.topic, &a.action) {
            (Some(_), None) => {
                self.msg_type(what, &a.type_name)?;
                a.type_name.clone()
            }
            (None, Some(_)) => {
                let goal = format!("{}_Goal", a.type_name);
                self.msg_type(what, &goal).map_err(|_| {
                    self.err(
                        what,
                        &a.type_name,
                        "not a known action type (give its .action file in [[interfaces]])",
                    )
                })?;
                goal
            }
            _ => return Err(self.err(what, "topic", "give either topic or action")),
        };
        self.message(what, &message_type, &a.message)
    }

    /// Checks that `table` is a value of `message_type`, field by field.
    fn message(&self, what: &str, message_type: &str, table: &toml::Table) -> Result<(), MappingError> {
        let def = self
            .registry
            .msg(message_type)
            .map_err(|e| self.err(what, message_type, e.to_string()))?;
        if let Some(k) = table.keys().find(|k| !def.fields.iter().any(|f| &f.name == *k)) {
            return Err(self.err(what, k, format!("{message_type} has no such field")));
        }
        let value = Value::from_toml(&toml::Value::Table(table.clone()))
            .ok_or_else(|| self.err(what, "message", "dates are not message values"))?;
        self.registry
            .encode(message_type, &value)
            .map(drop)
            .map_err(|e| self.err(what, "message", e.to_string()))
    }
}

impl Condition {
    /// Whether `value` (a message or response) meets the condition.
    pub(crate) fn holds(&self, value: &Value) -> bool {
        let Some(v) = self.source.read(value) else {
            return false;
        };
        let v = &v;
        if let Some([lo, hi]) = self.between {
            // On a yaw, [lo, hi] with lo > hi is the arc through ±π.
            return v.as_f64().is_some_and(|x| {
                if lo <= hi {
                    lo <= x && x <= hi
                } else {
                    x >= lo || x <= hi
                }
            });
        }
        if let Some(want) = &self.equals {
            return match (v, want) {
                (Value::Bool(a), toml::Value::Boolean(b)) => a == b,
                (Value::Str(a), toml::Value::String(b)) => a == b,
                (v, toml::Value::Integer(i)) => v.as_f64() == Some(*i as f64),
                (v, toml::Value::Float(f)) => v.as_f64() == Some(*f),
                _ => false,
            };
        }
        match (v.as_f64(), self.below, self.above) {
            (Some(x), Some(b), _) => x < b,
            (Some(x), _, Some(a)) => x > a,
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
[zenoh]
connect = ["tcp/127.0.0.1:7447"]

[[atom]]
name = "at_end"
topic = "/corridor/at_end"
type = "std_msgs/msg/Bool"
equals = true

[[atom]]
name = "near_wall"
topic = "/corridor/range"
type = "sensor_msgs/msg/Range"
field = "range"
below = 0.5

[[fluent]]
name = "position"
topic = "/corridor/position"
type = "std_msgs/msg/Int32"

[[action]]
name = "forward"
topic = "/corridor/cmd"
type = "std_msgs/msg/Int32"
message = { data = 1 }

[reward]
topic = "/corridor/reward"
type = "std_msgs/msg/Float64"

[reset]
service = "/corridor/reset"
type = "std_srvs/srv/Empty"
"#;

    fn err(text: &str) -> String {
        parse(Path::new("m.toml"), text).unwrap_err().to_string()
    }

    #[test]
    fn a_good_mapping_loads_and_its_conditions_hold() {
        let l = parse(Path::new("m.toml"), GOOD).unwrap();
        assert_eq!(l.mapping.atoms.len(), 2);
        let near = &l.mapping.atoms[1];
        let range = |r: f64| Value::fields([("range", Value::Float(r))]);
        assert!(near.holds(&range(0.25)));
        assert!(!near.holds(&range(0.75)));
        assert!(l.mapping.atoms[0].holds(&Value::fields([("data", Value::Bool(true))])));
        assert!(!l.mapping.atoms[0].holds(&Value::fields([("data", Value::Bool(false))])));
        assert!(l.mapping.plan_state.publish);
        assert_eq!(l.mapping.plan_state.namespace, "/learnpnp");
        let off = format!("{GOOD}\n[plan_state]\npublish = false\nnamespace = \"/robot_1/plan\"\n");
        let off = parse(Path::new("m.toml"), &off).unwrap().mapping.plan_state;
        assert!(!off.publish);
        assert_eq!(off.namespace, "/robot_1/plan");
    }

    #[test]
    fn bad_entries_name_file_entry_and_token() {
        let e = err(&GOOD.replace("field = \"range\"", "field = \"rnage\""));
        assert!(
            e.contains("m.toml: [[atom]] 'near_wall': 'rnage'") && e.contains("its fields: header"),
            "{e}"
        );
        let e = err(&GOOD.replace("std_msgs/msg/Bool", "std_msgs/msg/Boool"));
        assert!(
            e.contains("[[atom]] 'at_end': 'std_msgs/msg/Boool'") && e.contains("unknown type"),
            "{e}"
        );
        let e = err(&GOOD.replace("equals = true", "equals = 3"));
        assert!(e.contains("[[atom]] 'at_end': '3'"), "{e}");
        let e = err(&GOOD.replace("{ data = 1 }", "{ data = \"x\" }"));
        assert!(
            e.contains("[[action]] 'forward': 'message'") && e.contains("expected an integer"),
            "{e}"
        );
        let e = err(&GOOD.replace("{ data = 1 }", "{ dta = 1 }"));
        assert!(e.contains("[[action]] 'forward': 'dta'"), "{e}");
        let e = err(&GOOD.replace("name = \"position\"", "name = \"at_end\""));
        assert!(e.contains("'at_end': named twice"), "{e}");
        let e = err(&format!("{GOOD}\n[plan_state]\nnamespace = \"learnpnp\"\n"));
        assert!(
            e.contains("m.toml: [plan_state]: 'learnpnp': a namespace is absolute"),
            "{e}"
        );
        let e = err(&GOOD.replace("[reset]", "[rest]"));
        assert!(e.starts_with("m.toml: ") && e.contains("rest"), "{e}");
        let e = err(&GOOD.replace("std_srvs/srv/Empty", "std_msgs/msg/Empty"));
        assert!(e.contains("[reset]: 'std_msgs/msg/Empty'"), "{e}");
        let back =
            "[[action]]\nname = \"back\"\ntopic = \"/corridor/cmd\"\ntype = \"std_msgs/msg/Float64\"\n\n[reward]";
        let e = err(&GOOD.replacen("[reward]", back, 1));
        assert!(
            e.contains("[[action]] 'back': 'std_msgs/msg/Float64': '/corridor/cmd' is already mapped with the type std_msgs/msg/Int32"),
            "{e}"
        );
    }

    const POSE: &str = r#"
[zenoh]
connect = ["tcp/127.0.0.1:7447"]

[[interfaces]]
name = "geometry_msgs/msg/Point"
file = "Point.msg"

[[interfaces]]
name = "geometry_msgs/msg/Quaternion"
file = "Quaternion.msg"

[[interfaces]]
name = "geometry_msgs/msg/Pose"
file = "Pose.msg"

[[atom]]
name = "facing_east"
topic = "/robot/pose"
type = "geometry_msgs/msg/Pose"
field = "orientation"
derive = "yaw"
between = [-0.4, 0.4]

[[atom]]
name = "facing_north"
topic = "/robot/pose"
type = "geometry_msgs/msg/Pose"
field = "orientation"
derive = "yaw"
above = 1.2

[[atom]]
name = "facing_west"
topic = "/robot/pose"
type = "geometry_msgs/msg/Pose"
field = "orientation"
derive = "yaw"
between = [2.36, -2.36]

[[fluent]]
name = "heading"
topic = "/robot/pose"
type = "geometry_msgs/msg/Pose"
field = "orientation"
derive = "yaw"

[[action]]
name = "turn"
topic = "/robot/cmd"
type = "std_msgs/msg/Int32"
"#;

    /// A pose rotated by `roll` about x, then `yaw` about z (pitch 0).
    fn pose(roll: f64, yaw: f64) -> Value {
        let (sr, cr) = (roll / 2.0).sin_cos();
        let (sy, cy) = (yaw / 2.0).sin_cos();
        let q = Value::fields([
            ("x", Value::Float(sr * cy)),
            ("y", Value::Float(sr * sy)),
            ("z", Value::Float(cr * sy)),
            ("w", Value::Float(cr * cy)),
        ]);
        Value::fields([("position", Value::fields([])), ("orientation", q)])
    }

    #[test]
    fn a_yaw_is_derived_from_a_poses_quaternion_and_read_by_atoms_and_fluents() {
        let dir = std::env::temp_dir().join(format!("learnpnp-ros2-yaw-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("Point.msg"), "float64 x\nfloat64 y\nfloat64 z\n").unwrap();
        std::fs::write(
            dir.join("Quaternion.msg"),
            "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("Pose.msg"),
            "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
        )
        .unwrap();
        let loaded = parse(&dir.join("m.toml"), POSE);
        let bad = |text: String| parse(&dir.join("m.toml"), &text).unwrap_err().to_string();
        let on_a_number = bad(POSE.replacen("field = \"orientation\"", "field = \"orientation.z\"", 1));
        let of_a_point = bad(POSE.replacen("field = \"orientation\"", "field = \"position\"", 1));
        let backwards = bad(POSE.replacen(
            "field = \"orientation\"\nderive = \"yaw\"\nbetween = [-0.4, 0.4]",
            "field = \"orientation.z\"\nbetween = [0.4, -0.4]",
            1,
        ));
        std::fs::remove_dir_all(&dir).unwrap();
        let m = loaded.unwrap().mapping;
        let [east, north, west] = [&m.atoms[0], &m.atoms[1], &m.atoms[2]];
        let heading = &m.fluents[0].source;
        for roll in [0.0, 0.3, -1.0] {
            for (yaw, holds) in [
                (0.0, [true, false, false]),
                (0.3, [true, false, false]),
                (std::f64::consts::FRAC_PI_2, [false, true, false]),
                (3.0, [false, true, true]),
                (-3.0, [false, false, true]),
                (-std::f64::consts::FRAC_PI_2, [false, false, false]),
            ] {
                let p = pose(roll, yaw);
                assert!(
                    (heading.number(&p).unwrap() - yaw).abs() < 1e-12,
                    "roll {roll}, yaw {yaw}"
                );
                assert_eq!(
                    [east.holds(&p), north.holds(&p), west.holds(&p)],
                    holds,
                    "roll {roll}, yaw {yaw}"
                );
            }
        }
        // Facing exactly west: +π or -π, the same heading.
        assert!(west.holds(&pose(0.0, std::f64::consts::PI)) && west.holds(&pose(0.0, -std::f64::consts::PI)));
        assert!(!east.holds(&Value::fields([])), "no quaternion, no yaw");
        assert!(
            on_a_number.contains("[[atom]] 'facing_east': 'orientation.z'") && on_a_number.contains("not a message"),
            "{on_a_number}"
        );
        assert!(of_a_point.contains("no numeric 'w'"), "{of_a_point}");
        assert!(backwards.contains("the lower bound comes first"), "{backwards}");
    }
}
