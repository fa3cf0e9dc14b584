//! rmw_zenoh's key expressions, liveliness tokens and attachments
//! (ros2/rmw_zenoh `docs/design.md` and
//! `rmw_zenoh_cpp/src/detail/{liveliness_utils,attachment_helpers,qos}.cpp`).

use thiserror::Error;

/// Data key of a topic or service (design.md, "Topic and Service name mapping
/// to Zenoh key expressions"): `<domain_id>/<fully qualified name without its
/// outer slashes>/<DDS type name>/<type hash>`.
pub(crate) fn topic_key(domain: u32, name: &str, dds_type: &str, type_hash: &str) -> String {
    format!("{domain}/{}/{dds_type}/{type_hash}", name.trim_matches('/'))
}

/// A name with each `/` written `%` (design.md, "Graph Cache": mangled names;
/// an empty name is `%`, as an empty namespace is).
pub(crate) fn mangle(name: &str) -> String {
    if name.is_empty() {
        "%".into()
    } else {
        name.replace('/', "%")
    }
}

/// The kind of an entity in a liveliness token (design.md, "Graph Cache").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum EntityKind {
    /// `NN`: a node.
    Node,
    /// `MP`: a message publisher.
    Publisher,
    /// `MS`: a message subscription.
    Subscription,
    /// `SS`: a service server.
    ServiceServer,
    /// `SC`: a service client.
    ServiceClient,
}

impl EntityKind {
    /// Its two letters.
    pub(crate) fn code(self) -> &'static str {
        match self {
            EntityKind::Node => "NN",
            EntityKind::Publisher => "MP",
            EntityKind::Subscription => "MS",
            EntityKind::ServiceServer => "SS",
            EntityKind::ServiceClient => "SC",
        }
    }
}

/// rmw's QoS policies as numbers (rmw/types.h: reliability 1 reliable, 2 best
/// effort; durability 1 transient local, 2 volatile; history 1 keep last, 2
/// keep all; liveliness 1 automatic), durations as (sec, nsec).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Qos {
    /// Reliability.
    pub(crate) reliability: u8,
    /// Durability.
    pub(crate) durability: u8,
    /// History.
    pub(crate) history: u8,
    /// History depth.
    pub(crate) depth: u64,
    /// Deadline (sec, nsec).
    pub(crate) deadline: (u64, u64),
    /// Lifespan (sec, nsec).
    pub(crate) lifespan: (u64, u64),
    /// Liveliness.
    pub(crate) liveliness: u8,
    /// Liveliness lease (sec, nsec).
    pub(crate) lease: (u64, u64),
}

/// rmw's infinite duration (RMW_DURATION_INFINITE: `{9223372036, 854775807}`).
pub(crate) const INFINITE: (u64, u64) = (9_223_372_036, 854_775_807);

impl Default for Qos {
    /// rmw_zenoh's defaults (qos.cpp): reliable, volatile, keep last 42,
    /// infinite deadline, lifespan and lease, automatic liveliness.
    fn default() -> Self {
        Qos {
            reliability: 1,
            durability: 2,
            history: 1,
            depth: 42,
            deadline: INFINITE,
            lifespan: INFINITE,
            liveliness: 1,
            lease: INFINITE,
        }
    }
}

impl Qos {
    /// rclcpp's usual profile: the defaults with a history of `depth`.
    pub(crate) fn keep_last(depth: u64) -> Self {
        Qos {
            depth,
            ..Qos::default()
        }
    }

    /// The token's QoS field (liveliness_utils.cpp, `qos_to_keyexpr`): each
    /// value written only where it differs from rmw_zenoh's default;
    /// `reliability:durability:history,depth:deadline_s,deadline_ns:lifespan_s,lifespan_ns:liveliness,lease_s,lease_ns`.
    pub fn to_keyexpr(&self) -> String {
        let d = Qos::default();
        let f = |v: u64, dv: u64| if v == dv { String::new() } else { v.to_string() };
        format!(
            "{}:{}:{},{}:{},{}:{},{}:{},{},{}",
            f(self.reliability.into(), d.reliability.into()),
            f(self.durability.into(), d.durability.into()),
            f(self.history.into(), d.history.into()),
            f(self.depth, d.depth),
            f(self.deadline.0, d.deadline.0),
            f(self.deadline.1, d.deadline.1),
            f(self.lifespan.0, d.lifespan.0),
            f(self.lifespan.1, d.lifespan.1),
            f(self.liveliness.into(), d.liveliness.into()),
            f(self.lease.0, d.lease.0),
            f(self.lease.1, d.lease.1),
        )
    }
}

/// Who a liveliness token is for: the node and, but for a node's own token,
/// the topic or service.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entity<'a> {
    /// ROS_DOMAIN_ID.
    pub domain: u32,
    /// The Zenoh session id (hex, as zenoh prints it).
    pub zid: &'a str,
    /// The node's id within the session.
    pub(crate) node_id: u64,
    /// The entity's id (the node's own for a node).
    pub id: u64,
    /// Its kind.
    pub(crate) kind: EntityKind,
    /// SROS enclave (empty when not set).
    pub enclave: &'a str,
    /// The node's namespace (`/` or `/robot1`).
    pub namespace: &'a str,
    /// The node's name.
    pub node: &'a str,
    /// For all but nodes: (fully qualified name, DDS type name, type hash, QoS).
    pub topic: Option<(&'a str, &'a str, &'a str, Qos)>,
}

/// The admin space prefixing every token (liveliness_utils.cpp, ADMIN_SPACE).
pub(crate) const ADMIN_SPACE: &str = "@ros2_lv";

impl Entity<'_> {
    /// The liveliness token (design.md, "Graph Cache"):
    /// `@ros2_lv/<domain>/<zid>/<node id>/<entity id>/<kind>/<enclave>/<namespace>/<node>`,
    /// then for all but nodes `/<name>/<type>/<hash>/<qos>`, names mangled.
    pub fn token(&self) -> String {
        // The namespace "/" mangles to "%", as an empty one does.
        let ns = if self.namespace == "/" { "" } else { self.namespace };
        let mut key = format!(
            "{ADMIN_SPACE}/{}/{}/{}/{}/{}/{}/{}/{}",
            self.domain,
            self.zid,
            self.node_id,
            self.id,
            self.kind.code(),
            mangle(self.enclave),
            mangle(ns),
            mangle(self.node)
        );
        if let Some((name, ty, hash, qos)) = &self.topic {
            let fq = if name.starts_with('/') {
                name.to_string()
            } else {
                format!("/{name}")
            };
            key.push_str(&format!(
                "/{}/{}/{}/{}",
                mangle(&fq),
                mangle(ty),
                hash,
                qos.to_keyexpr()
            ));
        }
        key
    }
}

/// Length of a GID (rmw's RMW_GID_STORAGE_SIZE as rmw_zenoh fills it).
pub(crate) const GID_LEN: usize = 16;

/// The attachment of every publication, request and reply (design.md,
/// "Publishers", "Service Clients", "Service Servers"; attachment_helpers.cpp):
/// the sequence number (i64 little-endian), the source time in ns since the
/// epoch (i64 little-endian), the GID's length (one byte, 16) and the GID.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Attachment {
    /// The sequence number.
    pub(crate) sequence: i64,
    /// Source timestamp, ns since the UNIX epoch.
    pub(crate) timestamp_ns: i64,
    /// The publisher's or client's GID.
    pub(crate) gid: [u8; GID_LEN],
}

/// An attachment that is not rmw_zenoh's.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub(crate) enum AttachmentError {
    /// Not 33 bytes.
    #[error("attachment of {0} bytes, not 33 (sequence, time, GID length, GID)")]
    Length(usize),
    /// A GID length other than 16.
    #[error("attachment's GID length is {0}, not 16")]
    GidLength(u8),
}

impl Attachment {
    /// The 33 bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(33);
        out.extend_from_slice(&self.sequence.to_le_bytes());
        out.extend_from_slice(&self.timestamp_ns.to_le_bytes());
        out.push(GID_LEN as u8);
        out.extend_from_slice(&self.gid);
        out
    }

    /// Reads the 33 bytes.
    pub(crate) fn from_bytes(b: &[u8]) -> Result<Self, AttachmentError> {
        if b.len() != 33 {
            return Err(AttachmentError::Length(b.len()));
        }
        if b[16] as usize != GID_LEN {
            return Err(AttachmentError::GidLength(b[16]));
        }
        let mut seq = [0u8; 8];
        let mut ts = [0u8; 8];
        let mut gid = [0u8; GID_LEN];
        seq.copy_from_slice(&b[..8]);
        ts.copy_from_slice(&b[8..16]);
        gid.copy_from_slice(&b[17..]);
        Ok(Attachment {
            sequence: i64::from_le_bytes(seq),
            timestamp_ns: i64::from_le_bytes(ts),
            gid,
        })
    }
}

/// An entity's GID as rmw_zenoh derives it (rmw_zenoh_cpp
/// `src/detail/liveliness_utils.cpp`, `Entity`'s constructor): XXH3-128 of
/// the entity's liveliness token, the hash's low 64 bits then its high 64
/// bits, each little-endian (`memcpy` of `XXH128_hash_t`'s `low64`, `high64`).
pub(crate) fn gid_of(token: &str) -> [u8; GID_LEN] {
    xxhash_rust::xxh3::xxh3_128(token.as_bytes()).to_le_bytes()
}

/// ROS 2's action naming (design article "Actions"; rcl_action's names): the
/// action's services and topics under `<action>/_action/`.
pub mod action {
    /// The goal service.
    pub(crate) const SEND_GOAL: &str = "_action/send_goal";
    /// The result service.
    pub(crate) const GET_RESULT: &str = "_action/get_result";
    /// The cancel service (action_msgs/srv/CancelGoal).
    pub(crate) const CANCEL_GOAL: &str = "_action/cancel_goal";
    /// The feedback topic (`<Action>_FeedbackMessage`).
    pub(crate) const FEEDBACK: &str = "_action/feedback";
    /// The status topic (action_msgs/msg/GoalStatusArray).
    pub(crate) const STATUS: &str = "_action/status";

    /// A goal's status (action_msgs/msg/GoalStatus constants).
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum GoalStatus {
        /// 0: unknown.
        Unknown,
        /// 1: accepted.
        Accepted,
        /// 2: executing.
        Executing,
        /// 3: canceling.
        Canceling,
        /// 4: succeeded.
        Succeeded,
        /// 5: canceled.
        Canceled,
        /// 6: aborted.
        Aborted,
    }

    impl GoalStatus {
        /// The status of a code, or `None` for a code action_msgs does not define.
        pub(crate) fn from_code(code: i64) -> Option<Self> {
            Some(match code {
                0 => GoalStatus::Unknown,
                1 => GoalStatus::Accepted,
                2 => GoalStatus::Executing,
                3 => GoalStatus::Canceling,
                4 => GoalStatus::Succeeded,
                5 => GoalStatus::Canceled,
                6 => GoalStatus::Aborted,
                _ => return None,
            })
        }
    }

    /// `<action name>/<suffix>`.
    pub fn name(action: &str, suffix: &str) -> String {
        format!("{}/{suffix}", action.trim_end_matches('/'))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const STRING_HASH: &str = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18";
    const ADD_HASH: &str = "RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a";

    /// design.md, "Topic and Service name mapping to Zenoh key expressions", its three examples.
    #[test]
    fn data_keys_match_the_design_examples() {
        assert_eq!(
            topic_key(0, "/chatter", "std_msgs::msg::dds_::String_", STRING_HASH),
            format!("0/chatter/std_msgs::msg::dds_::String_/{STRING_HASH}")
        );
        assert_eq!(
            topic_key(0, "/robot1/chatter", "std_msgs::msg::dds_::String_", STRING_HASH),
            format!("0/robot1/chatter/std_msgs::msg::dds_::String_/{STRING_HASH}")
        );
        assert_eq!(
            topic_key(
                2,
                "/add_two_ints",
                "example_interfaces::srv::dds_::AddTwoInts_",
                ADD_HASH
            ),
            format!("2/add_two_ints/example_interfaces::srv::dds_::AddTwoInts_/{ADD_HASH}")
        );
    }

    /// design.md, "Graph Cache", its five examples (demo_nodes_cpp, domain 2).
    #[test]
    fn liveliness_tokens_match_the_design_examples() {
        let node = |zid, node, id, kind, topic| Entity {
            domain: 2,
            zid,
            node_id: 0,
            id,
            kind,
            enclave: "",
            namespace: "/",
            node,
            topic,
        };
        assert_eq!(
            node(
                "aac3178e146ba6f1fc6e6a4085e77f21",
                "listener",
                0,
                EntityKind::Node,
                None
            )
            .token(),
            "@ros2_lv/2/aac3178e146ba6f1fc6e6a4085e77f21/0/0/NN/%/%/listener"
        );
        let string = "std_msgs::msg::dds_::String_";
        assert_eq!(
            node(
                "aac3178e146ba6f1fc6e6a4085e77f21",
                "listener",
                10,
                EntityKind::Subscription,
                Some(("/chatter", string, STRING_HASH, Qos::keep_last(10)))
            )
            .token(),
            format!(
                "@ros2_lv/2/aac3178e146ba6f1fc6e6a4085e77f21/0/10/MS/%/%/listener/%chatter/{string}/{STRING_HASH}/::,10:,:,:,,"
            )
        );
        assert_eq!(
            node(
                "8b20917502ee955ac4476e0266340d5c",
                "talker",
                10,
                EntityKind::Publisher,
                Some(("/chatter", string, STRING_HASH, Qos::keep_last(7)))
            )
            .token(),
            format!(
                "@ros2_lv/2/8b20917502ee955ac4476e0266340d5c/0/10/MP/%/%/talker/%chatter/{string}/{STRING_HASH}/::,7:,:,:,,"
            )
        );
        let add = "example_interfaces::srv::dds_::AddTwoInts_";
        for (zid, name, kind, code) in [
            (
                "f9980ee0495eaafb3e38f0d19e2eae12",
                "add_two_ints_server",
                EntityKind::ServiceServer,
                "SS",
            ),
            (
                "e1dc8d1b45ae8717fce78689cc655685",
                "add_two_ints_client",
                EntityKind::ServiceClient,
                "SC",
            ),
        ] {
            assert_eq!(
                node(
                    zid,
                    name,
                    10,
                    kind,
                    Some(("/add_two_ints", add, ADD_HASH, Qos::keep_last(10)))
                )
                .token(),
                format!("@ros2_lv/2/{zid}/0/10/{code}/%/%/{name}/%add_two_ints/{add}/{ADD_HASH}/::,10:,:,:,,")
            );
        }
    }

    /// GIDs as the reference xxHash computes them: libxxhash 0.8.1's
    /// `XXH3_128bits` (Debian's libxxhash0, called through Python's ctypes:
    /// `low64.to_bytes(8, "little") + high64.to_bytes(8, "little")`) on design.md's
    /// node and publisher tokens and on a token longer than 240 bytes (xxHash's
    /// three input-length paths: 17-128, 129-240, longer).
    #[test]
    fn gids_are_xxh3_128_of_the_token_as_rmw_zenoh_makes_them() {
        let long = "@ros2_lv/0/0123456789abcdef0123456789abcdef/0/3/SC/%/%/learnpnp_world/%a%very%long%namespace%for%a%robot%with%many%parts/corridor_msgs::action::dds_::Move_SendGoal_/RIHS01_c588ea9aa1d1b1fb851ed432419fe25742f3702a20907375ab1f76991434d2b4/::,10:,:,:,,";
        for (token, gid) in [
            (
                "@ros2_lv/2/aac3178e146ba6f1fc6e6a4085e77f21/0/0/NN/%/%/listener".to_string(),
                "49877999dacb858702d11ac823785912",
            ),
            (
                format!(
                    "@ros2_lv/2/8b20917502ee955ac4476e0266340d5c/0/10/MP/%/%/talker/%chatter/std_msgs::msg::dds_::String_/{STRING_HASH}/::,7:,:,:,,"
                ),
                "ac170f31eadcd9ff0cd86d7a17907d1c",
            ),
            (long.to_string(), "94c625a8b258b76610b1432c3b17190f"),
        ] {
            let hex: String = gid_of(&token).iter().map(|b| format!("{b:02x}")).collect();
            assert_eq!(hex, gid, "{} bytes", token.len());
        }
        assert_eq!(long.len(), 249);
    }

    #[test]
    fn qos_writes_only_what_differs_from_the_defaults() {
        assert_eq!(Qos::default().to_keyexpr(), "::,:,:,:,,");
        let q = Qos {
            reliability: 2,
            durability: 1,
            ..Qos::keep_last(1)
        };
        assert_eq!(q.to_keyexpr(), "2:1:,1:,:,:,,");
    }

    /// design.md, "Publishers": 8 bytes sequence, 8 bytes time, 1 byte GID length, 16 bytes GID.
    #[test]
    fn attachments_are_sequence_time_length_gid() {
        let a = Attachment {
            sequence: 1,
            timestamp_ns: 0x0102_0304_0506_0708,
            gid: [0xab; 16],
        };
        let b = a.to_bytes();
        assert_eq!(&b[..8], &[1, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(&b[8..16], &[8, 7, 6, 5, 4, 3, 2, 1]);
        assert_eq!(b[16], 16);
        assert_eq!(&b[17..], &[0xab; 16]);
        assert_eq!(Attachment::from_bytes(&b).unwrap(), a);
        assert_eq!(Attachment::from_bytes(&b[..20]), Err(AttachmentError::Length(20)));
        let mut bad = b.clone();
        bad[16] = 8;
        assert_eq!(Attachment::from_bytes(&bad), Err(AttachmentError::GidLength(8)));
    }

    #[test]
    fn action_names_and_statuses() {
        assert_eq!(action::name("/move", action::SEND_GOAL), "/move/_action/send_goal");
        assert_eq!(action::GoalStatus::from_code(4), Some(action::GoalStatus::Succeeded));
        assert_eq!(action::GoalStatus::from_code(9), None);
    }
}
