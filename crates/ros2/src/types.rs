//! ROS 2 interface types: their fields (from `.msg`, `.srv` and `.action`
//! text), their RIHS01 type hashes, and CDR encoding of their values.
//!
//! The hash is REP-2016's (rosidl_generator_type_description, as rmw_zenoh's
//! design.md section "Topic and Service name mapping to Zenoh key
//! expressions" names it): the type's description (name, and each field's
//! name, type id, capacity, string capacity and nested type name) followed by
//! every type it references, sorted by name, written as JSON with `", "` and
//! `": "` separators and no default values, then SHA-256, printed
//! `RIHS01_<hex>`. A service is a type with three fields (`request_message`,
//! `response_message`, `event_message`); an action's goal, result and
//! feedback become the services `_SendGoal` and `_GetResult` and the message
//! `_FeedbackMessage` (ROS 2's action design, rosidl's action synthesis).

use std::collections::{BTreeMap, BTreeSet};

use thiserror::Error;

use crate::cdr::{CdrError, Reader, Writer};

/// A primitive field type of `.msg` files.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Prim {
    /// `bool`.
    Bool,
    /// `byte` (IDL octet).
    Byte,
    /// `char` (an alias of uint8 in ROS 2 `.msg`).
    Char,
    /// `int8`.
    I8,
    /// `uint8`.
    U8,
    /// `int16`.
    I16,
    /// `uint16`.
    U16,
    /// `int32`.
    I32,
    /// `uint32`.
    U32,
    /// `int64`.
    I64,
    /// `uint64`.
    U64,
    /// `float32`.
    F32,
    /// `float64`.
    F64,
    /// `string`.
    String,
    /// `string<=N`: at most N bytes.
    BoundedString(usize),
}

impl Prim {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "bool" => Prim::Bool,
            "byte" => Prim::Byte,
            "char" => Prim::Char,
            "int8" => Prim::I8,
            "uint8" => Prim::U8,
            "int16" => Prim::I16,
            "uint16" => Prim::U16,
            "int32" => Prim::I32,
            "uint32" => Prim::U32,
            "int64" => Prim::I64,
            "uint64" => Prim::U64,
            "float32" => Prim::F32,
            "float64" => Prim::F64,
            "string" => Prim::String,
            _ => Prim::BoundedString(s.strip_prefix("string<=")?.parse().ok().filter(|&n| n > 0)?),
        })
    }

    /// type_description_interfaces/msg/FieldType's id (char is uint8, byte is BYTE).
    fn type_id(self) -> u32 {
        match self {
            Prim::I8 => 2,
            Prim::U8 | Prim::Char => 3,
            Prim::I16 => 4,
            Prim::U16 => 5,
            Prim::I32 => 6,
            Prim::U32 => 7,
            Prim::I64 => 8,
            Prim::U64 => 9,
            Prim::F32 => 10,
            Prim::F64 => 11,
            Prim::Bool => 15,
            Prim::Byte => 16,
            Prim::String => 17,
            Prim::BoundedString(_) => 21,
        }
    }

    /// type_description_interfaces/msg/FieldType's `string_capacity`: a bounded string's bound.
    fn string_capacity(self) -> usize {
        match self {
            Prim::BoundedString(n) => n,
            _ => 0,
        }
    }
}

/// A field's element type.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Elem {
    /// A primitive.
    Prim(Prim),
    /// Another message, by full name (`pkg/msg/Name`).
    Nested(String),
}

/// How many elements a field holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Shape {
    /// One.
    Single,
    /// A fixed array (`T[N]`).
    Array(usize),
    /// A bounded sequence (`T[<=N]`).
    Bounded(usize),
    /// An unbounded sequence (`T[]`).
    Sequence,
}

/// A field of a message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Field {
    /// Its name.
    pub name: String,
    /// Its element type.
    pub(crate) elem: Elem,
    /// Its shape.
    pub(crate) shape: Shape,
}

/// A message type: its full name and its fields.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MsgDef {
    /// `pkg/msg/Name` (or `pkg/srv/Name_Request`, `pkg/action/Name_Goal`, ...).
    pub name: String,
    /// Its fields in order.
    pub(crate) fields: Vec<Field>,
}

/// A bad interface definition or value.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum TypeError {
    /// A line of a definition that is not `TYPE NAME`.
    #[error("{interface}: line {line} '{text}': {why}")]
    Syntax {
        /// The interface being read.
        interface: String,
        /// 1-based line.
        line: usize,
        /// The line.
        text: String,
        /// What is wrong.
        why: String,
    },
    /// A name that is not `pkg/kind/Name`.
    #[error("'{0}' is not a full interface name (pkg/msg/Name, pkg/srv/Name or pkg/action/Name)")]
    Name(String),
    /// A type no definition was given for.
    #[error("unknown type '{0}' (give its .msg, .srv or .action file in [[interfaces]])")]
    Unknown(String),
    /// A value that does not fit its type.
    #[error("{type_name}: field '{field}': {why}")]
    Value {
        /// The message type.
        type_name: String,
        /// The field.
        field: String,
        /// What is wrong.
        why: String,
    },
    /// A payload that does not decode.
    #[error("{type_name}: {error}")]
    Cdr {
        /// The message type.
        type_name: String,
        /// The CDR error.
        error: CdrError,
    },
}

/// Splits `pkg/kind/Name`.
fn split_name(name: &str) -> Result<(&str, &str, &str), TypeError> {
    let mut it = name.split('/');
    match (it.next(), it.next(), it.next(), it.next()) {
        (Some(p), Some(k), Some(n), None)
            if !p.is_empty() && !n.is_empty() && ["msg", "srv", "action"].contains(&k) =>
        {
            Ok((p, k, n))
        }
        _ => Err(TypeError::Name(name.to_string())),
    }
}

/// The DDS type name rmw_zenoh puts in keys and tokens (design.md, "Topic and
/// Service name mapping"): `pkg/msg/Name` is `pkg::msg::dds_::Name_`.
pub(crate) fn dds_name(name: &str) -> Result<String, TypeError> {
    let (p, k, n) = split_name(name)?;
    Ok(format!("{p}::{k}::dds_::{n}_"))
}

/// All the message types known: the built-in ones and those read from files.
#[derive(Debug, Clone)]
pub struct Registry {
    msgs: BTreeMap<String, MsgDef>,
    /// Services (and actions' services): name to (request, response) message names.
    services: BTreeMap<String, (String, String)>,
}

/// Built-in definitions: (name, .msg text). Facts from ROS 2's
/// common_interfaces, rcl_interfaces and unique_identifier_msgs (Jazzy).
const BUILTIN_MSGS: &[(&str, &str)] = &[
    ("builtin_interfaces/msg/Time", "int32 sec\nuint32 nanosec"),
    ("std_msgs/msg/Bool", "bool data"),
    ("std_msgs/msg/Empty", ""),
    ("std_msgs/msg/Float32", "float32 data"),
    ("std_msgs/msg/Float64", "float64 data"),
    ("std_msgs/msg/Int32", "int32 data"),
    ("std_msgs/msg/String", "string data"),
    ("std_msgs/msg/Header", "builtin_interfaces/Time stamp\nstring frame_id"),
    (
        "sensor_msgs/msg/Range",
        "std_msgs/Header header\nuint8 ULTRASOUND=0\nuint8 INFRARED=1\nuint8 radiation_type\n\
         float32 field_of_view\nfloat32 min_range\nfloat32 max_range\nfloat32 range",
    ),
    ("unique_identifier_msgs/msg/UUID", "uint8[16] uuid"),
    (
        "service_msgs/msg/ServiceEventInfo",
        "uint8 event_type\nbuiltin_interfaces/Time stamp\nchar[16] client_gid\nint64 sequence_number",
    ),
    (
        "action_msgs/msg/GoalInfo",
        "unique_identifier_msgs/UUID goal_id\nbuiltin_interfaces/Time stamp",
    ),
    ("action_msgs/msg/GoalStatus", "GoalInfo goal_info\nint8 status"),
    ("action_msgs/msg/GoalStatusArray", "GoalStatus[] status_list"),
];

/// Built-in services: (name, request text, response text).
const BUILTIN_SRVS: &[(&str, &str, &str)] = &[
    ("std_srvs/srv/Empty", "", ""),
    ("std_srvs/srv/Trigger", "", "bool success\nstring message"),
    (
        "action_msgs/srv/CancelGoal",
        "GoalInfo goal_info",
        "int8 return_code\nGoalInfo[] goals_canceling",
    ),
];

impl Default for Registry {
    fn default() -> Self {
        Self::new()
    }
}

impl Registry {
    /// The built-in types.
    pub fn new() -> Self {
        let mut r = Registry {
            msgs: BTreeMap::new(),
            services: BTreeMap::new(),
        };
        for (name, text) in BUILTIN_MSGS {
            r.add_msg(name, text)
                .unwrap_or_else(|e| unreachable!("built-in {name}: {e}"));
        }
        for (name, req, resp) in BUILTIN_SRVS {
            r.add_srv(name, req, resp)
                .unwrap_or_else(|e| unreachable!("built-in {name}: {e}"));
        }
        r
    }

    /// A message's definition.
    pub fn msg(&self, name: &str) -> Result<&MsgDef, TypeError> {
        self.msgs.get(name).ok_or_else(|| TypeError::Unknown(name.to_string()))
    }

    /// A service's request and response message names.
    pub fn service(&self, name: &str) -> Result<(&str, &str), TypeError> {
        self.services
            .get(name)
            .map(|(a, b)| (a.as_str(), b.as_str()))
            .ok_or_else(|| TypeError::Unknown(name.to_string()))
    }

    /// Reads `.msg` text as the message `name` (`pkg/msg/Name`); constants are skipped.
    pub(crate) fn add_msg(&mut self, name: &str, text: &str) -> Result<(), TypeError> {
        let (pkg, _, _) = split_name(name)?;
        let mut fields = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let syntax = |why: &str| TypeError::Syntax {
                interface: name.to_string(),
                line: i + 1,
                text: raw.to_string(),
                why: why.to_string(),
            };
            let mut parts = line.split_whitespace();
            let (Some(ty), Some(rest)) = (parts.next(), parts.next()) else {
                return Err(syntax("expected TYPE NAME"));
            };
            if rest.contains('=') || parts.clone().next().is_some_and(|p| p.starts_with('=')) {
                continue; // a constant
            }
            let (base, shape) = match ty.find('[') {
                None => (ty, Shape::Single),
                Some(b) => {
                    let inner = ty[b + 1..].strip_suffix(']').ok_or_else(|| syntax("unclosed '['"))?;
                    let shape = if inner.is_empty() {
                        Shape::Sequence
                    } else if let Some(n) = inner.strip_prefix("<=") {
                        Shape::Bounded(n.parse().map_err(|_| syntax("bad bound"))?)
                    } else {
                        Shape::Array(inner.parse().map_err(|_| syntax("bad array size"))?)
                    };
                    (&ty[..b], shape)
                }
            };
            if base.starts_with("string<=") && Prim::parse(base).is_none() {
                return Err(syntax("bad string bound (string<=N, N a positive integer)"));
            }
            let elem = match Prim::parse(base) {
                Some(p) => Elem::Prim(p),
                None => Elem::Nested(match base.split('/').collect::<Vec<_>>()[..] {
                    [n] => format!("{pkg}/msg/{n}"),
                    [p, n] => format!("{p}/msg/{n}"),
                    [p, k, n] => format!("{p}/{k}/{n}"),
                    _ => return Err(syntax("bad type name")),
                }),
            };
            fields.push(Field {
                name: rest.to_string(),
                elem,
                shape,
            });
        }
        self.msgs.insert(
            name.to_string(),
            MsgDef {
                name: name.to_string(),
                fields,
            },
        );
        Ok(())
    }

    /// Adds a service from its request and response text, with its
    /// `_Request`, `_Response` and `_Event` messages.
    pub(crate) fn add_srv(&mut self, name: &str, request: &str, response: &str) -> Result<(), TypeError> {
        let (req, resp) = (format!("{name}_Request"), format!("{name}_Response"));
        self.add_msg(&req, request)?;
        self.add_msg(&resp, response)?;
        self.add_service_of(name, req, resp);
        Ok(())
    }

    /// Registers `name` as the service of two known messages, with its event message.
    fn add_service_of(&mut self, name: &str, req: String, resp: String) {
        let field = |name: &str, elem: Elem, shape| Field {
            name: name.into(),
            elem,
            shape,
        };
        let event = format!("{name}_Event");
        self.msgs.insert(
            event.clone(),
            MsgDef {
                name: event,
                fields: vec![
                    field(
                        "info",
                        Elem::Nested("service_msgs/msg/ServiceEventInfo".into()),
                        Shape::Single,
                    ),
                    field("request", Elem::Nested(req.clone()), Shape::Bounded(1)),
                    field("response", Elem::Nested(resp.clone()), Shape::Bounded(1)),
                ],
            },
        );
        self.services.insert(name.to_string(), (req, resp));
    }

    /// Adds a file's text by its interface name: `.msg` for `pkg/msg/N`,
    /// `.srv` (request `---` response) for `pkg/srv/N`, `.action` (goal `---`
    /// result `---` feedback) for `pkg/action/N`.
    pub(crate) fn add_interface(&mut self, name: &str, text: &str) -> Result<(), TypeError> {
        let (_, kind, _) = split_name(name)?;
        let parts: Vec<&str> = split_sections(text);
        let syntax = |why: String| TypeError::Syntax {
            interface: name.to_string(),
            line: 0,
            text: String::new(),
            why,
        };
        match (kind, parts.as_slice()) {
            ("msg", [m]) => self.add_msg(name, m),
            ("srv", [req, resp]) => self.add_srv(name, req, resp),
            ("action", [goal, result, feedback]) => self.add_action(name, goal, result, feedback),
            (k, p) => Err(syntax(format!(
                "a {k} has {} sections separated by '---', not {}",
                match k {
                    "msg" => 1,
                    "srv" => 2,
                    _ => 3,
                },
                p.len()
            ))),
        }
    }

    /// Adds an action: its goal, result and feedback, and the services and
    /// message ROS 2 builds from them (`_SendGoal`, `_GetResult`, `_FeedbackMessage`).
    pub(crate) fn add_action(&mut self, name: &str, goal: &str, result: &str, feedback: &str) -> Result<(), TypeError> {
        let (g, r, f) = (
            format!("{name}_Goal"),
            format!("{name}_Result"),
            format!("{name}_Feedback"),
        );
        self.add_msg(&g, goal)?;
        self.add_msg(&r, result)?;
        self.add_msg(&f, feedback)?;
        let uuid = "unique_identifier_msgs/UUID goal_id";
        self.add_srv(
            &format!("{name}_SendGoal"),
            &format!("{uuid}\n{g} goal"),
            "bool accepted\nbuiltin_interfaces/Time stamp",
        )?;
        self.add_srv(&format!("{name}_GetResult"), uuid, &format!("int8 status\n{r} result"))?;
        self.add_msg(&format!("{name}_FeedbackMessage"), &format!("{uuid}\n{f} feedback"))
    }

    /// The type description of a message, or of a service (a name added as one).
    fn description(&self, name: &str) -> Result<MsgDef, TypeError> {
        if let Some((req, resp)) = self.services.get(name) {
            let nested = |n: &str, t: String| Field {
                name: n.into(),
                elem: Elem::Nested(t),
                shape: Shape::Single,
            };
            return Ok(MsgDef {
                name: name.to_string(),
                fields: vec![
                    nested("request_message", req.clone()),
                    nested("response_message", resp.clone()),
                    nested("event_message", format!("{name}_Event")),
                ],
            });
        }
        let mut def = self.msg(name)?.clone();
        if def.fields.is_empty() {
            // rosidl gives an empty structure one uint8 member.
            def.fields.push(empty_member());
        }
        Ok(def)
    }

    /// The RIHS01 hash of a message or service type (`RIHS01_<64 hex>`).
    pub(crate) fn type_hash(&self, name: &str) -> Result<String, TypeError> {
        let top = self.description(name)?;
        let mut refs = BTreeSet::new();
        let mut queue: Vec<String> = nested_of(&top);
        while let Some(n) = queue.pop() {
            if refs.insert(n.clone()) {
                queue.extend(nested_of(&self.description(&n)?));
            }
        }
        let mut json = format!(
            "{{\"type_description\": {}, \"referenced_type_descriptions\": [",
            describe(&top)
        );
        for (i, n) in refs.iter().enumerate() {
            if i > 0 {
                json.push_str(", ");
            }
            json.push_str(&describe(&self.description(n)?));
        }
        json.push_str("]}");
        let digest = ring::digest::digest(&ring::digest::SHA256, json.as_bytes());
        let hex: String = digest.as_ref().iter().map(|b| format!("{b:02x}")).collect();
        Ok(format!("RIHS01_{hex}"))
    }

    /// Encodes a value of message type `name` as a CDR payload.
    pub(crate) fn encode(&self, name: &str, value: &Value) -> Result<Vec<u8>, TypeError> {
        let mut w = Writer::new();
        self.write_struct(&mut w, name, value)?;
        Ok(w.finish())
    }

    /// Decodes a CDR payload of message type `name`.
    pub(crate) fn decode(&self, name: &str, payload: &[u8]) -> Result<Value, TypeError> {
        let cdr = |error| TypeError::Cdr {
            type_name: name.to_string(),
            error,
        };
        let mut r = Reader::new(payload).map_err(cdr)?;
        self.read_struct(&mut r, name).map_err(|e| match e {
            ReadError::Cdr(error) => cdr(error),
            ReadError::Type(t) => t,
        })
    }

    fn write_struct(&self, w: &mut Writer, name: &str, value: &Value) -> Result<(), TypeError> {
        let def = self.msg(name)?;
        if def.fields.is_empty() {
            w.u8(0);
            return Ok(());
        }
        for f in &def.fields {
            let bad = |why: String| TypeError::Value {
                type_name: name.to_string(),
                field: f.name.clone(),
                why,
            };
            let v = value.get(&f.name);
            match f.shape {
                Shape::Single => self.write_elem(w, &f.elem, v).map_err(bad)?,
                shape => {
                    let items: &[Value] = match v {
                        None => &[],
                        Some(Value::List(items)) => items,
                        Some(other) => return Err(bad(format!("expected a list, got {other:?}"))),
                    };
                    match shape {
                        Shape::Array(n) if items.len() != n && !items.is_empty() => {
                            return Err(bad(format!("expected {n} elements, got {}", items.len())));
                        }
                        Shape::Array(n) => {
                            for i in 0..n {
                                self.write_elem(w, &f.elem, items.get(i)).map_err(&bad)?;
                            }
                            continue;
                        }
                        Shape::Bounded(n) if items.len() > n => {
                            return Err(bad(format!("at most {n} elements, got {}", items.len())));
                        }
                        _ => {}
                    }
                    w.u32(u32::try_from(items.len()).map_err(|_| bad("too many elements".into()))?);
                    for item in items {
                        self.write_elem(w, &f.elem, Some(item)).map_err(&bad)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// Writes one element; a missing value is the type's zero.
    fn write_elem(&self, w: &mut Writer, elem: &Elem, v: Option<&Value>) -> Result<(), String> {
        let int = |v: Option<&Value>| -> Result<i128, String> {
            match v {
                None => Ok(0),
                Some(Value::Int(i)) => Ok(i128::from(*i)),
                Some(Value::Bool(b)) => Ok(i128::from(*b)),
                Some(o) => Err(format!("expected an integer, got {o:?}")),
            }
        };
        let range = |i: i128, lo: i128, hi: i128| {
            if (lo..=hi).contains(&i) {
                Ok(i)
            } else {
                Err(format!("{i} is out of range {lo}..={hi}"))
            }
        };
        let float = |v: Option<&Value>| -> Result<f64, String> {
            match v {
                None => Ok(0.0),
                Some(Value::Float(f)) => Ok(*f),
                Some(Value::Int(i)) => Ok(*i as f64),
                Some(o) => Err(format!("expected a number, got {o:?}")),
            }
        };
        match elem {
            Elem::Nested(n) => {
                let empty = Value::Struct(BTreeMap::new());
                self.write_struct(w, n, v.unwrap_or(&empty))
                    .map_err(|e| e.to_string())?;
            }
            Elem::Prim(p) => match p {
                Prim::Bool => match v {
                    None => w.bool(false),
                    Some(Value::Bool(b)) => w.bool(*b),
                    Some(o) => return Err(format!("expected a boolean, got {o:?}")),
                },
                Prim::Byte | Prim::Char | Prim::U8 => w.u8(range(int(v)?, 0, 255)? as u8),
                Prim::I8 => w.i8(range(int(v)?, -128, 127)? as i8),
                Prim::I16 => w.i16(range(int(v)?, i16::MIN.into(), i16::MAX.into())? as i16),
                Prim::U16 => w.u16(range(int(v)?, 0, u16::MAX.into())? as u16),
                Prim::I32 => w.i32(range(int(v)?, i32::MIN.into(), i32::MAX.into())? as i32),
                Prim::U32 => w.u32(range(int(v)?, 0, u32::MAX.into())? as u32),
                Prim::I64 => w.i64(range(int(v)?, i64::MIN.into(), i64::MAX.into())? as i64),
                Prim::U64 => w.u64(range(int(v)?, 0, i64::MAX.into())? as u64),
                Prim::F32 => w.f32(float(v)? as f32),
                Prim::F64 => w.f64(float(v)?),
                Prim::String | Prim::BoundedString(_) => match v {
                    None => w.string(""),
                    Some(Value::Str(s)) if s.len() > p.string_capacity() && p.string_capacity() > 0 => {
                        return Err(format!(
                            "a string of {} bytes, more than its bound {}",
                            s.len(),
                            p.string_capacity()
                        ));
                    }
                    Some(Value::Str(s)) => w.string(s),
                    Some(o) => return Err(format!("expected a string, got {o:?}")),
                },
            },
        }
        Ok(())
    }

    fn read_struct(&self, r: &mut Reader<'_>, name: &str) -> Result<Value, ReadError> {
        let def = self.msg(name).map_err(ReadError::Type)?;
        let mut out = BTreeMap::new();
        if def.fields.is_empty() {
            r.u8()?;
            return Ok(Value::Struct(out));
        }
        for f in &def.fields {
            let v = match f.shape {
                Shape::Single => self.read_elem(r, &f.elem)?,
                Shape::Array(n) => Value::List((0..n).map(|_| self.read_elem(r, &f.elem)).collect::<Result<_, _>>()?),
                Shape::Bounded(bound) => {
                    let n = r.bounded_count(bound)?;
                    Value::List((0..n).map(|_| self.read_elem(r, &f.elem)).collect::<Result<_, _>>()?)
                }
                Shape::Sequence => {
                    let n = r.count()?;
                    Value::List((0..n).map(|_| self.read_elem(r, &f.elem)).collect::<Result<_, _>>()?)
                }
            };
            out.insert(f.name.clone(), v);
        }
        Ok(Value::Struct(out))
    }

    fn read_elem(&self, r: &mut Reader<'_>, elem: &Elem) -> Result<Value, ReadError> {
        Ok(match elem {
            Elem::Nested(n) => self.read_struct(r, n)?,
            Elem::Prim(p) => match p {
                Prim::Bool => Value::Bool(r.bool()?),
                Prim::Byte | Prim::Char | Prim::U8 => Value::Int(r.u8()?.into()),
                Prim::I8 => Value::Int(r.i8()?.into()),
                Prim::I16 => Value::Int(r.i16()?.into()),
                Prim::U16 => Value::Int(r.u16()?.into()),
                Prim::I32 => Value::Int(r.i32()?.into()),
                Prim::U32 => Value::Int(r.u32()?.into()),
                Prim::I64 => Value::Int(r.i64()?),
                Prim::U64 => Value::Int(i64::try_from(r.u64()?).unwrap_or(i64::MAX)),
                Prim::F32 => Value::Float(r.f32()?.into()),
                Prim::F64 => Value::Float(r.f64()?),
                Prim::String => Value::Str(r.string()?),
                Prim::BoundedString(n) => Value::Str(r.bounded_string(*n)?),
            },
        })
    }
}

/// Splits interface text at its `---` lines.
fn split_sections(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut pos = 0;
    for line in text.split_inclusive('\n') {
        if line.trim() == "---" {
            out.push(&text[start..pos]);
            start = pos + line.len();
        }
        pos += line.len();
    }
    out.push(&text[start..]);
    out
}

enum ReadError {
    Cdr(CdrError),
    Type(TypeError),
}

impl From<CdrError> for ReadError {
    fn from(e: CdrError) -> Self {
        ReadError::Cdr(e)
    }
}

/// rosidl's member of an empty structure.
fn empty_member() -> Field {
    Field {
        name: "structure_needs_at_least_one_member".into(),
        elem: Elem::Prim(Prim::U8),
        shape: Shape::Single,
    }
}

fn nested_of(def: &MsgDef) -> Vec<String> {
    def.fields
        .iter()
        .filter_map(|f| match &f.elem {
            Elem::Nested(n) => Some(n.clone()),
            Elem::Prim(_) => None,
        })
        .collect()
}

/// One type description as REP-2016's hashed JSON.
fn describe(def: &MsgDef) -> String {
    let fields: Vec<String> = def
        .fields
        .iter()
        .map(|f| {
            let (base, string_capacity, nested) = match &f.elem {
                Elem::Prim(p) => (p.type_id(), p.string_capacity(), String::new()),
                Elem::Nested(n) => (1, 0, n.clone()),
            };
            let (offset, capacity) = match f.shape {
                Shape::Single => (0, 0),
                Shape::Array(n) => (48, n),
                Shape::Bounded(n) => (96, n),
                Shape::Sequence => (144, 0),
            };
            format!(
                "{{\"name\": {}, \"type\": {{\"type_id\": {}, \"capacity\": {capacity}, \"string_capacity\": {string_capacity}, \"nested_type_name\": {}}}}}",
                json_str(&f.name),
                base + offset,
                json_str(&nested)
            )
        })
        .collect();
    format!(
        "{{\"type_name\": {}, \"fields\": [{}]}}",
        json_str(&def.name),
        fields.join(", ")
    )
}

fn json_str(s: &str) -> String {
    serde_json::Value::String(s.to_string()).to_string()
}

/// A decoded (or to-be-encoded) message value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A boolean.
    Bool(bool),
    /// Any integer.
    Int(i64),
    /// Any float.
    Float(f64),
    /// A string.
    Str(String),
    /// An array or sequence.
    List(Vec<Value>),
    /// A message: its fields by name.
    Struct(BTreeMap<String, Value>),
}

impl Value {
    /// A message with these fields.
    pub(crate) fn fields<const N: usize>(fields: [(&str, Value); N]) -> Self {
        Value::Struct(fields.into_iter().map(|(k, v)| (k.to_string(), v)).collect())
    }

    /// A field of a message.
    pub(crate) fn get(&self, field: &str) -> Option<&Value> {
        match self {
            Value::Struct(m) => m.get(field),
            _ => None,
        }
    }

    /// A field by a dotted path (`header.stamp.sec`).
    pub fn path(&self, path: &str) -> Option<&Value> {
        path.split('.').try_fold(self, |v, f| v.get(f))
    }

    /// Sets the field at a dotted path, making the messages on the way
    /// (a value that is not a message on the way is replaced by one).
    pub(crate) fn set_path(&mut self, path: &str, value: Value) {
        let mut at = self;
        for field in path.split('.') {
            if !matches!(at, Value::Struct(_)) {
                *at = Value::Struct(BTreeMap::new());
            }
            let Value::Struct(fields) = at else { return };
            at = fields
                .entry(field.to_string())
                .or_insert(Value::Struct(BTreeMap::new()));
        }
        *at = value;
    }

    /// The value as a number (booleans as 0 or 1).
    pub(crate) fn as_f64(&self) -> Option<f64> {
        match self {
            Value::Bool(b) => Some(f64::from(u8::from(*b))),
            Value::Int(i) => Some(*i as f64),
            Value::Float(f) => Some(*f),
            _ => None,
        }
    }

    /// From TOML (the mapping file's values).
    pub(crate) fn from_toml(v: &toml::Value) -> Option<Self> {
        Some(match v {
            toml::Value::Boolean(b) => Value::Bool(*b),
            toml::Value::Integer(i) => Value::Int(*i),
            toml::Value::Float(f) => Value::Float(*f),
            toml::Value::String(s) => Value::Str(s.clone()),
            toml::Value::Array(a) => Value::List(a.iter().map(Value::from_toml).collect::<Option<_>>()?),
            toml::Value::Table(t) => Value::Struct(
                t.iter()
                    .map(|(k, v)| Some((k.clone(), Value::from_toml(v)?)))
                    .collect::<Option<_>>()?,
            ),
            toml::Value::Datetime(_) => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Golden hashes from rmw_zenoh's docs/design.md ("Topic and Service name
    /// mapping to Zenoh key expressions", examples with demo_nodes_cpp).
    #[test]
    fn hashes_match_rmw_zenoh_design_examples() {
        let mut r = Registry::new();
        assert_eq!(
            r.type_hash("std_msgs/msg/String").unwrap(),
            "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
        );
        r.add_interface(
            "example_interfaces/srv/AddTwoInts",
            "int64 a\nint64 b\n---\nint64 sum\n",
        )
        .unwrap();
        assert_eq!(
            r.type_hash("example_interfaces/srv/AddTwoInts").unwrap(),
            "RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a"
        );
    }

    /// The same hashes as an independent implementation computes them
    /// (zenoh-ros2-sdk 0.1.8, from the .msg/.srv files the Python test ships;
    /// its robot declares these in its liveliness tokens).
    #[test]
    fn hashes_agree_with_zenoh_ros2_sdk() {
        let mut r = Registry::new();
        r.add_interface("corridor_msgs/srv/Reset", "int32 start\n---\nbool success\n")
            .unwrap();
        for (t, h) in [
            (
                "std_msgs/msg/Bool",
                "feb91e995ff9ebd09c0cb3d2aed18b11077585839fb5db80193b62d74528f6c9",
            ),
            (
                "std_msgs/msg/Int32",
                "b6578ded3c58c626cfe8d1a6fb6e04f706f97e9f03d2727c9ff4e74b1cef0deb",
            ),
            (
                "std_msgs/msg/Float64",
                "705ba9c3d1a09df43737eb67095534de36fd426c0587779bda2bc51fe790182a",
            ),
            (
                "sensor_msgs/msg/Range",
                "9430b1915b94d4268ff903679e8ecd09b6a67d331bd028738ec1eeb592891ebd",
            ),
            (
                "corridor_msgs/srv/Reset",
                "56cbcd15f5eccf7dd116b888aed6522a8431d36b51c6f8de2a8788d8395766d1",
            ),
        ] {
            assert_eq!(r.type_hash(t).unwrap(), format!("RIHS01_{h}"), "{t}");
        }
    }

    /// An action's synthesized types hash as an independent implementation
    /// computes them: rosbags 0.11.9's `Typestore.hash_rihs01`, the types built
    /// as rosidl builds them, by
    /// `python python/tests/ros2/action_types.py example_interfaces/action/Fibonacci Fibonacci.action`
    /// (Fibonacci.action: `int32 order`, `---`, `int32[] sequence`, `---`,
    /// `int32[] sequence`); that script checks its construction on design.md's
    /// two golden hashes first (python/tests/test_ros2_types.py).
    #[test]
    fn action_hashes_agree_with_rosbags() {
        let mut r = Registry::new();
        r.add_interface(
            "example_interfaces/action/Fibonacci",
            "int32 order\n---\nint32[] sequence\n---\nint32[] sequence\n",
        )
        .unwrap();
        for (t, h) in [
            (
                "example_interfaces/action/Fibonacci_SendGoal",
                "d1a57fb2a4afe8c21e34fb10db206f16ce6729b28531141472df92277c55b557",
            ),
            (
                "example_interfaces/action/Fibonacci_GetResult",
                "1b0de0d5d29dc955d92f546706568428632771db13ec84c15ec1c1a59f424a57",
            ),
            (
                "example_interfaces/action/Fibonacci_FeedbackMessage",
                "c1de71afd52e49a89c53d8262366884185bc0a02f78ce051c4e46b0a7fe59bb2",
            ),
        ] {
            assert_eq!(r.type_hash(t).unwrap(), format!("RIHS01_{h}"), "{t}");
        }
    }

    /// A message with bounded strings, bounded sequences and fixed arrays:
    /// its hash as rosbags 0.11.9's `Typestore.hash_rihs01` computes it
    /// (`Types().msg("corridor_msgs/msg/Bounded", BOUNDED)` of
    /// python/tests/ros2/action_types.py, then `.hash(...)`): type ids 21 +
    /// 48/96/144 and `string_capacity` for bounded strings, `capacity` for
    /// arrays and bounded sequences.
    const BOUNDED: &str = "string<=10 name\nint32[<=3] values\nstring<=5[2] tags\nstring<=4[<=2] codes\n\
                           float64[4] pose\nstring[<=2] notes\nbuiltin_interfaces/msg/Time[<=2] stamps\n";

    #[test]
    fn bounded_types_hash_as_rosbags_computes_them() {
        let mut r = Registry::new();
        r.add_interface("corridor_msgs/msg/Bounded", BOUNDED).unwrap();
        assert_eq!(
            r.type_hash("corridor_msgs/msg/Bounded").unwrap(),
            "RIHS01_cbbf08fb619976f0484fbb0161dd02824eb60945b40eb2b149c053a2b51fd9b0"
        );
        let e = r.add_msg("x/msg/Y", "string<=x name").unwrap_err();
        assert!(e.to_string().contains("bad string bound"), "{e}");
    }

    #[test]
    fn bounds_are_kept_on_encoding_and_refused_over_on_decoding() {
        let mut r = Registry::new();
        r.add_interface("corridor_msgs/msg/Bounded", BOUNDED).unwrap();
        let t = "corridor_msgs/msg/Bounded";
        let ints = |v: &[i64]| Value::List(v.iter().map(|&i| Value::Int(i)).collect());
        let strs = |v: &[&str]| Value::List(v.iter().map(|&s| Value::Str(s.into())).collect());
        let good = Value::fields([
            ("name", Value::Str("robot".into())),
            ("values", ints(&[1, 2, 3])),
            ("tags", strs(&["a", "bcdef"])),
            ("codes", strs(&["abcd"])),
            (
                "pose",
                Value::List([1.0, 2.0, 3.0, 4.0].into_iter().map(Value::Float).collect()),
            ),
            ("notes", strs(&[])),
            ("stamps", Value::List(vec![])),
        ]);
        let bytes = r.encode(t, &good).unwrap();
        assert_eq!(r.decode(t, &bytes).unwrap(), good);
        let over = |field: &str, v: Value| {
            let Value::Struct(mut m) = good.clone() else {
                unreachable!()
            };
            m.insert(field.into(), v);
            r.encode(t, &Value::Struct(m)).unwrap_err().to_string()
        };
        assert!(over("name", Value::Str("elevenbytes".into())).contains("more than its bound 10"));
        assert!(over("values", ints(&[1, 2, 3, 4])).contains("at most 3 elements"));
        assert!(over("tags", strs(&["a", "bcdefg"])).contains("more than its bound 5"));
        assert!(over("pose", ints(&[1])).contains("expected 4 elements"));
        // A peer's payload over a bound is refused, never trusted: the
        // `name` string of 11 bytes, then the `values` sequence of 4.
        let mut w = Writer::new();
        w.string("elevenbytes");
        let e = r.decode(t, &w.finish()).unwrap_err();
        assert!(
            matches!(
                e,
                TypeError::Cdr {
                    error: CdrError::OverBound {
                        what: "string",
                        count: 11,
                        bound: 10,
                        ..
                    },
                    ..
                }
            ),
            "{e}"
        );
        let mut w = Writer::new();
        w.string("robot");
        w.u32(4);
        for i in 0..4 {
            w.i32(i);
        }
        let e = r.decode(t, &w.finish()).unwrap_err();
        assert!(
            e.to_string()
                .contains("sequence at byte 12 has 4 elements, more than its bound 3"),
            "{e}"
        );
    }

    #[test]
    fn dds_names_follow_the_design() {
        assert_eq!(dds_name("std_msgs/msg/String").unwrap(), "std_msgs::msg::dds_::String_");
        assert_eq!(
            dds_name("corridor_msgs/action/Move_SendGoal").unwrap(),
            "corridor_msgs::action::dds_::Move_SendGoal_"
        );
        assert!(dds_name("String").is_err());
    }

    #[test]
    fn values_round_trip_through_cdr() {
        let r = Registry::new();
        let range = Value::fields([
            (
                "header",
                Value::fields([
                    (
                        "stamp",
                        Value::fields([("sec", Value::Int(3)), ("nanosec", Value::Int(9))]),
                    ),
                    ("frame_id", Value::Str("base".into())),
                ]),
            ),
            ("radiation_type", Value::Int(1)),
            ("field_of_view", Value::Float(0.5)),
            ("min_range", Value::Float(0.0)),
            ("max_range", Value::Float(4.0)),
            ("range", Value::Float(0.25)),
        ]);
        let bytes = r.encode("sensor_msgs/msg/Range", &range).unwrap();
        assert_eq!(r.decode("sensor_msgs/msg/Range", &bytes).unwrap(), range);
        assert_eq!(
            r.encode("std_msgs/msg/Empty", &Value::fields([])).unwrap(),
            [0, 1, 0, 0, 0]
        );
        let f64 = r
            .encode("std_msgs/msg/Float64", &Value::fields([("data", Value::Float(-1.0))]))
            .unwrap();
        assert_eq!(f64, [0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0xf0, 0xbf]);
        let status = Value::fields([(
            "status_list",
            Value::List(vec![Value::fields([("status", Value::Int(4))])]),
        )]);
        let bytes = r.encode("action_msgs/msg/GoalStatusArray", &status).unwrap();
        let back = r.decode("action_msgs/msg/GoalStatusArray", &bytes).unwrap();
        assert_eq!(
            back.path("status_list").and_then(|l| match l {
                Value::List(v) => v[0].get("status").cloned(),
                _ => None,
            }),
            Some(Value::Int(4))
        );
    }

    #[test]
    fn bad_values_and_payloads_are_named() {
        let r = Registry::new();
        let e = r
            .encode("std_msgs/msg/Int32", &Value::fields([("data", Value::Int(1 << 40))]))
            .unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
        let e = r.decode("std_msgs/msg/Bool", &[0, 1, 0, 0, 7]).unwrap_err();
        assert!(
            e.to_string().contains("std_msgs/msg/Bool") && e.to_string().contains("not 0 or 1"),
            "{e}"
        );
        assert!(matches!(r.type_hash("nope/msg/X"), Err(TypeError::Unknown(_))));
    }

    #[test]
    fn an_action_brings_its_services_and_feedback_message() {
        let mut r = Registry::new();
        r.add_interface(
            "corridor_msgs/action/Move",
            "int32 direction\n---\nbool moved\n---\nfloat32 progress\n",
        )
        .unwrap();
        assert_eq!(
            r.service("corridor_msgs/action/Move_SendGoal").unwrap(),
            (
                "corridor_msgs/action/Move_SendGoal_Request",
                "corridor_msgs/action/Move_SendGoal_Response"
            )
        );
        for t in [
            "corridor_msgs/action/Move_SendGoal",
            "corridor_msgs/action/Move_GetResult",
            "corridor_msgs/action/Move_FeedbackMessage",
            "action_msgs/srv/CancelGoal",
            "action_msgs/msg/GoalStatusArray",
        ] {
            assert!(r.type_hash(t).unwrap().starts_with("RIHS01_"), "{t}");
        }
        let e = r.add_interface("x/action/Y", "int32 a\n---\nbool b\n").unwrap_err();
        assert!(e.to_string().contains("3 sections"), "{e}");
    }
}
