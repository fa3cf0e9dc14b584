//! The world a mapping file makes of a ROS 2 robot: a
//! [`ServedWorld`](learnpnp_system::multiprocess::world_host::ServedWorld) whose state is the latest message on each mapped topic,
//! stepped in lock-step (each step waits for the robot's answer, so the run
//! goes at the robot's rate).

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use learnpnp_system::ipc::world::{ActionStatus, Vocabulary};
use learnpnp_system::multiprocess::world_host::{Observation, ServedWorld, StepResult};
use serde::Serialize;

use crate::keys::action::{self as names, GoalStatus};
use crate::mapping::{ActionMap, Condition, Loaded, Source};
use crate::node::{Client, Node, Publisher, Received, Refusal, Ros2Error, Subscription};
use crate::types::Value;

/// What was refused or went wrong, by kind (the world reports them and goes on).
#[derive(Debug, Default, Clone, Serialize, PartialEq, Eq)]
pub struct Counts {
    /// Payloads that were not their type's CDR.
    pub malformed_cdr: u64,
    /// Messages on a mapped topic with another type name or type hash.
    pub wrong_type: u64,
    /// Missing or malformed attachments.
    pub bad_attachment: u64,
    /// Action statuses action_msgs does not define (or a result that is not final).
    pub unknown_action_status: u64,
    /// Answers, results or replies that did not come in time.
    pub timeouts: u64,
    /// Goals the robot rejected.
    pub goals_rejected: u64,
    /// Feedback messages received.
    pub feedback: u64,
    /// Steps taken.
    pub steps: u64,
    /// Episodes started.
    pub resets: u64,
}

/// The robot's state as the subscriptions leave it.
#[derive(Debug, Default)]
struct State {
    /// Latest message per topic.
    latest: BTreeMap<String, Value>,
    /// Answers received.
    answers: u64,
    /// Reward received on the reward topic since it was last taken.
    reward: f64,
    counts: Counts,
}

/// State shared with the subscription callbacks.
#[derive(Debug, Default)]
struct Shared {
    state: Mutex<State>,
    changed: Condvar,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    fn refuse(&self, refusal: &Refusal) {
        let mut s = self.lock();
        match refusal {
            Refusal::MalformedCdr { .. } => s.counts.malformed_cdr += 1,
            Refusal::WrongType { .. } => s.counts.wrong_type += 1,
            Refusal::BadAttachment { .. } => s.counts.bad_attachment += 1,
        }
        drop(s);
        eprintln!("learnpnp-ros2-world: refused: {refusal}");
    }
}

/// How a plan action reaches the robot.
enum Command {
    /// A message on a topic.
    Topic(Box<(Arc<Publisher>, Value)>),
    /// A goal to a ROS 2 action.
    Action(Box<Goal>),
}

/// A ROS 2 action's clients: one set per action, however many plan actions
/// send it goals (as one rclcpp action client would).
struct ActionClients {
    send_goal: Client,
    get_result: Client,
    cancel: Client,
}

/// A ROS 2 action's clients and the goal to send.
struct Goal {
    clients: Arc<ActionClients>,
    goal: Value,
}

/// A service polled after each step for a value.
struct Polled {
    client: Client,
    field: String,
}

/// A ROS 2 robot as a world.
pub struct Ros2World {
    loaded: Loaded,
    node: Node,
    shared: Arc<Shared>,
    commands: Vec<Command>,
    reset: Option<Client>,
    reward_service: Option<Polled>,
    end_service: Option<(Client, Condition)>,
    end_value: Option<Value>,
    _subscriptions: Vec<Subscription>,
    goals: AtomicU64,
    steps: u32,
    timeout: Duration,
}

/// The topic key of a source (the latest message is stored under its name).
fn topic_of(s: &Source) -> Option<&str> {
    s.topic.as_deref()
}

impl Ros2World {
    /// Declares the world's node on `node`'s session and everything the mapping uses.
    pub fn new(loaded: Loaded, node: Node) -> Result<Self, Ros2Error> {
        let shared = Arc::new(Shared::default());
        let m = &loaded.mapping;
        let mut topics: BTreeMap<String, String> = BTreeMap::new();
        let sources = m
            .atoms
            .iter()
            .map(|a| &a.source)
            .chain(m.fluents.iter().map(|f| &f.source))
            .chain(m.end.iter().map(|e| &e.source));
        for s in sources {
            if let Some(t) = topic_of(s) {
                topics.insert(node.qualify(t), s.type_name.clone());
            }
        }
        let mut subscriptions = Vec::new();
        for (topic, type_name) in &topics {
            let sh = Arc::clone(&shared);
            let name = topic.clone();
            subscriptions.push(node.subscribe(topic, type_name, move |r| match r {
                Ok(Received { value, .. }) => {
                    sh.lock().latest.insert(name.clone(), value);
                    sh.changed.notify_all();
                }
                Err(refusal) => sh.refuse(&refusal),
            })?);
        }
        if let Some(r) = m.reward.as_ref().filter(|r| r.source.topic.is_some()) {
            let sh = Arc::clone(&shared);
            let field = r.source.field.clone();
            let topic = r.source.topic.clone().unwrap_or_default();
            subscriptions.push(node.subscribe(&topic, &r.source.type_name, move |r| match r {
                Ok(Received { value, .. }) => {
                    sh.lock().reward += value.path(&field).and_then(Value::as_f64).unwrap_or(0.0);
                }
                Err(refusal) => sh.refuse(&refusal),
            })?);
        }
        if let Some(a) = &m.answer {
            let sh = Arc::clone(&shared);
            subscriptions.push(node.subscribe(&a.topic, &a.type_name, move |r| match r {
                Ok(_) => {
                    sh.lock().answers += 1;
                    sh.changed.notify_all();
                }
                Err(refusal) => sh.refuse(&refusal),
            })?);
        }
        let mut commands = Vec::new();
        let mut made = Made::default();
        for a in &m.actions {
            commands.push(command(&node, a, &shared, &mut subscriptions, &mut made)?);
        }
        let reset = m
            .reset
            .as_ref()
            .map(|r| node.client(&r.service, &r.type_name))
            .transpose()?;
        let reward_service = m
            .reward
            .as_ref()
            .and_then(|r| r.source.service.as_ref().map(|s| (s, r)))
            .map(|(s, r)| {
                Ok::<_, Ros2Error>(Polled {
                    client: node.client(s, &r.source.type_name)?,
                    field: r.source.field.clone(),
                })
            })
            .transpose()?;
        let end_service = m
            .end
            .as_ref()
            .and_then(|e| e.source.service.as_ref().map(|s| (s, e)))
            .map(|(s, e)| Ok::<_, Ros2Error>((node.client(s, &e.source.type_name)?, e.clone())))
            .transpose()?;
        let timeout = Duration::from_millis(m.timeout_ms);
        Ok(Ros2World {
            loaded,
            node,
            shared,
            commands,
            reset,
            reward_service,
            end_service,
            end_value: None,
            _subscriptions: subscriptions,
            goals: AtomicU64::new(0),
            steps: 0,
            timeout,
        })
    }

    /// What was refused or timed out so far.
    pub fn counts(&self) -> Counts {
        self.shared.lock().counts.clone()
    }

    /// Answers received so far.
    fn answers(&self) -> u64 {
        self.shared.lock().answers
    }

    /// Waits for an answer after `before` (when the mapping has one).
    fn await_answer(&self, before: u64) {
        if self.loaded.mapping.answer.is_none() {
            return;
        }
        let deadline = Instant::now() + self.timeout;
        let mut s = self.shared.lock();
        while s.answers <= before {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                s.counts.timeouts += 1;
                drop(s);
                eprintln!(
                    "learnpnp-ros2-world: no answer on '{}' within {} ms",
                    self.loaded
                        .mapping
                        .answer
                        .as_ref()
                        .map(|a| a.topic.as_str())
                        .unwrap_or_default(),
                    self.timeout.as_millis()
                );
                return;
            }
            s = self
                .shared
                .changed
                .wait_timeout(s, left)
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .0;
        }
    }

    /// Counts a failed call and says what it was.
    fn failed(&self, what: &str, e: &Ros2Error) {
        let mut s = self.shared.lock();
        match e {
            Ros2Error::NoReply { .. } => s.counts.timeouts += 1,
            Ros2Error::Refused { refusal, .. } => match refusal.as_ref() {
                Refusal::MalformedCdr { .. } => s.counts.malformed_cdr += 1,
                Refusal::WrongType { .. } => s.counts.wrong_type += 1,
                Refusal::BadAttachment { .. } => s.counts.bad_attachment += 1,
            },
            _ => {}
        }
        drop(s);
        eprintln!("learnpnp-ros2-world: {what}: {e}");
    }

    /// Runs a ROS 2 action's goal to its end: the action's status.
    fn run_goal(&self, clients: &ActionClients, goal: &Value) -> ActionStatus {
        let ActionClients {
            send_goal,
            get_result,
            cancel,
        } = clients;
        let n = self.goals.fetch_add(1, Ordering::Relaxed);
        // A goal id unique in the run: the counter and the process id.
        let mut uuid = [0u8; 16];
        uuid[..8].copy_from_slice(&n.to_le_bytes());
        uuid[8..12].copy_from_slice(&std::process::id().to_le_bytes());
        let id = Value::fields([(
            "uuid",
            Value::List(uuid.iter().map(|b| Value::Int(i64::from(*b))).collect()),
        )]);
        let request = Value::fields([("goal_id", id.clone()), ("goal", goal.clone())]);
        match send_goal.call(&request, self.timeout) {
            Ok(r) if r.get("accepted") == Some(&Value::Bool(true)) => {}
            Ok(_) => {
                self.shared.lock().counts.goals_rejected += 1;
                return ActionStatus::Failed;
            }
            Err(e) => {
                self.failed("send_goal", &e);
                return ActionStatus::Failed;
            }
        }
        match get_result.call(&Value::fields([("goal_id", id.clone())]), self.timeout) {
            Ok(r) => {
                let code = r.get("status").and_then(Value::as_f64).map_or(-1, |c| c as i64);
                match GoalStatus::from_code(code) {
                    Some(GoalStatus::Succeeded) => ActionStatus::Finished,
                    Some(GoalStatus::Canceled | GoalStatus::Aborted) => ActionStatus::Failed,
                    other => {
                        self.shared.lock().counts.unknown_action_status += 1;
                        eprintln!(
                            "learnpnp-ros2-world: refused: result status {code} ({}), taken as failed",
                            if other.is_some() {
                                "not final"
                            } else {
                                "not an action_msgs status"
                            }
                        );
                        ActionStatus::Failed
                    }
                }
            }
            Err(e) => {
                self.failed("get_result", &e);
                let info = Value::fields([("goal_info", Value::fields([("goal_id", id)]))]);
                if let Err(e) = cancel.call(&info, self.timeout) {
                    self.failed("cancel_goal", &e);
                }
                ActionStatus::Failed
            }
        }
    }

    /// Reads `source`'s field from the latest message.
    fn latest(&self, source: &Source) -> Option<Value> {
        let topic = self.node.qualify(topic_of(source)?);
        self.shared.lock().latest.get(&topic).cloned()
    }

    /// The step's reward: the constant, what came on the reward topic, or the service's answer.
    fn take_reward(&self) -> f64 {
        let mut reward = self.loaded.mapping.step_reward + std::mem::take(&mut self.shared.lock().reward);
        if let Some(p) = &self.reward_service {
            match p.client.call(&Value::fields([]), self.timeout) {
                Ok(v) => reward += v.path(&p.field).and_then(Value::as_f64).unwrap_or(0.0),
                Err(e) => self.failed("reward service", &e),
            }
        }
        reward
    }

    fn poll_end(&mut self) {
        if let Some((client, _)) = &self.end_service {
            match client.call(&Value::fields([]), self.timeout) {
                Ok(v) => self.end_value = Some(v),
                Err(e) => self.failed("end service", &e),
            }
        }
    }
}

/// The publishers and action clients made so far, by full name: one per
/// topic or ROS 2 action, however many plan actions use it.
#[derive(Default)]
struct Made {
    publishers: BTreeMap<String, Arc<Publisher>>,
    clients: BTreeMap<String, Arc<ActionClients>>,
}

/// Prepares a plan action's command; a topic's publisher and a ROS 2
/// action's clients and subscriptions are made once (`made`).
fn command(
    node: &Node,
    a: &ActionMap,
    shared: &Arc<Shared>,
    subs: &mut Vec<Subscription>,
    made: &mut Made,
) -> Result<Command, Ros2Error> {
    let message = Value::from_toml(&toml::Value::Table(a.message.clone())).unwrap_or_else(|| Value::fields([]));
    if let Some(topic) = &a.topic {
        let publisher = match made.publishers.get(&node.qualify(topic)) {
            Some(p) => Arc::clone(p),
            None => {
                let p = Arc::new(node.publisher(topic, &a.type_name)?);
                made.publishers.insert(node.qualify(topic), Arc::clone(&p));
                p
            }
        };
        return Ok(Command::Topic(Box::new((publisher, message))));
    }
    let action = a.action.clone().unwrap_or_default();
    if let Some(c) = made.clients.get(&node.qualify(&action)) {
        return Ok(Command::Action(Box::new(Goal {
            clients: Arc::clone(c),
            goal: message,
        })));
    }
    let t = &a.type_name;
    let sh = Arc::clone(shared);
    subs.push(node.subscribe(
        &names::name(&action, names::FEEDBACK),
        &format!("{t}_FeedbackMessage"),
        move |r| match r {
            Ok(_) => sh.lock().counts.feedback += 1,
            Err(refusal) => sh.refuse(&refusal),
        },
    )?);
    let sh = Arc::clone(shared);
    subs.push(node.subscribe(
        &names::name(&action, names::STATUS),
        "action_msgs/msg/GoalStatusArray",
        move |r| match r {
            Ok(Received { value, .. }) => {
                if let Some(Value::List(list)) = value.get("status_list") {
                    for s in list {
                        let code = s.get("status").and_then(Value::as_f64).map_or(-1, |c| c as i64);
                        if GoalStatus::from_code(code).is_none() {
                            sh.lock().counts.unknown_action_status += 1;
                            eprintln!("learnpnp-ros2-world: refused: goal status {code} is not an action_msgs status");
                        }
                    }
                }
            }
            Err(refusal) => sh.refuse(&refusal),
        },
    )?);
    let c = Arc::new(ActionClients {
        send_goal: node.client(&names::name(&action, names::SEND_GOAL), &format!("{t}_SendGoal"))?,
        get_result: node.client(&names::name(&action, names::GET_RESULT), &format!("{t}_GetResult"))?,
        cancel: node.client(&names::name(&action, names::CANCEL_GOAL), "action_msgs/srv/CancelGoal")?,
    });
    made.clients.insert(node.qualify(&action), Arc::clone(&c));
    Ok(Command::Action(Box::new(Goal {
        clients: c,
        goal: message,
    })))
}

impl ServedWorld for Ros2World {
    fn vocabulary(&self) -> Vocabulary {
        let m = &self.loaded.mapping;
        Vocabulary {
            atoms: m.atoms.iter().map(|a| a.name.clone()).collect(),
            fluents: m.fluents.iter().map(|f| f.name.clone()).collect(),
            actions: m.actions.iter().map(|a| a.name.clone()).collect(),
            agents: 1,
        }
    }

    fn reset(&mut self, _seed: Option<u64>) {
        self.steps = 0;
        self.shared.lock().counts.resets += 1;
        let before = self.answers();
        if let Some(reset) = &self.reset {
            let request = self
                .loaded
                .mapping
                .reset
                .as_ref()
                .and_then(|r| Value::from_toml(&toml::Value::Table(r.request.clone())))
                .unwrap_or_else(|| Value::fields([]));
            let mut tries = 0;
            while let Err(e) = reset.call(&request, self.timeout) {
                self.failed("reset", &e);
                tries += 1;
                if tries == 5 {
                    // The robot is gone: end the world so that the supervisor sees it.
                    eprintln!("error: learnpnp-ros2-world: the robot's reset service did not answer {tries} times");
                    std::process::exit(1);
                }
            }
        }
        self.await_answer(before);
        self.shared.lock().reward = 0.0;
        self.poll_end();
    }

    fn observe(&self, _agent: usize) -> Observation {
        let m = &self.loaded.mapping;
        let atoms = m
            .atoms
            .iter()
            .enumerate()
            .filter(|(_, a)| self.latest(&a.source).is_some_and(|v| a.holds(&v)))
            .map(|(i, _)| i)
            .collect();
        let fluents = m
            .fluents
            .iter()
            .map(|f| {
                self.latest(&f.source)
                    .and_then(|v| v.path(&f.source.field).and_then(Value::as_f64))
                    .unwrap_or(0.0)
            })
            .collect();
        Observation { atoms, fluents }
    }

    fn step(&mut self, actions: &[Option<usize>]) -> Vec<StepResult> {
        self.steps += 1;
        self.shared.lock().counts.steps += 1;
        let before = self.answers();
        let status = match actions.first().copied().flatten().and_then(|a| self.commands.get(a)) {
            None => ActionStatus::None,
            Some(Command::Topic(t)) => match t.0.publish(&t.1) {
                Ok(()) => ActionStatus::Finished,
                Err(e) => {
                    self.failed("command", &e);
                    ActionStatus::Failed
                }
            },
            Some(Command::Action(g)) => self.run_goal(&g.clients, &g.goal),
        };
        if status != ActionStatus::None {
            self.await_answer(before);
        }
        let reward = self.take_reward();
        self.poll_end();
        let mut out = vec![
            StepResult {
                reward: 0.0,
                action: ActionStatus::None,
            };
            actions.len()
        ];
        if let Some(first) = out.first_mut() {
            *first = StepResult { reward, action: status };
        }
        out
    }

    fn terminated(&self) -> bool {
        let Some(end) = &self.loaded.mapping.end else {
            return false;
        };
        match (&end.source.topic, &self.end_value) {
            (Some(_), _) => self.latest(&end.source).is_some_and(|v| end.holds(&v)),
            (None, Some(v)) => end.holds(v),
            (None, None) => false,
        }
    }

    fn truncated(&self) -> bool {
        self.loaded.mapping.max_steps.is_some_and(|m| self.steps >= m)
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::AtomicI64;

    use zenoh::Wait;

    use super::*;
    use crate::mapping;
    use crate::node::tests::loopback_pair;

    const MAPPING: &str = r#"
timeout_ms = 3000
[zenoh]
connect = ["tcp/127.0.0.1:9"]

[[interfaces]]
name = "corridor_msgs/action/Move"
file = "Move.action"

[[atom]]
name = "moved"
topic = "/robot/moved"
type = "std_msgs/msg/Bool"
equals = true

[[action]]
name = "forward"
action = "/robot/move"
type = "corridor_msgs/action/Move"
message = { direction = 1 }
"#;

    /// The action path against an action server made of this crate's own
    /// services and publishers (the Python test's robot uses topics: the
    /// zenoh-ros2-sdk has no actions).
    /// Whether `session` sees at least `n` service servers' liveliness
    /// tokens (`SS`) within about 55 s.
    fn sees_servers(session: &zenoh::Session, n: usize) -> bool {
        (0..100).any(|_| {
            let replies = session
                .liveliness()
                .get("@ros2_lv/0/**")
                .timeout(Duration::from_millis(500))
                .wait()
                .unwrap();
            let mut seen = 0;
            while let Ok(r) = replies.recv() {
                seen += r.result().is_ok_and(|s| s.key_expr().as_str().contains("/SS/")) as usize;
            }
            seen >= n || {
                std::thread::sleep(Duration::from_millis(50));
                false
            }
        })
    }

    #[test]
    fn a_plan_action_is_a_ros_2_goal_run_to_its_result_and_bad_statuses_are_refused() {
        let dir = std::env::temp_dir().join(format!("learnpnp-ros2-action-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("Move.action"),
            "int32 direction\n---\nbool moved\n---\nfloat32 progress\n",
        )
        .unwrap();
        std::fs::write(dir.join("m.toml"), MAPPING).unwrap();
        let loaded = mapping::load(&dir.join("m.toml")).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let registry = Arc::new(loaded.registry.clone());
        let (a, b) = loopback_pair();
        let world_node = Node::new(a.clone(), Arc::clone(&registry), 0, "/", "learnpnp_world").unwrap();
        let robot = Arc::new(Node::new(b, Arc::clone(&registry), 0, "/", "robot").unwrap());
        let status = Arc::new(AtomicI64::new(4));
        let moved = Arc::new(robot.publisher("/robot/moved", "std_msgs/msg/Bool").unwrap());
        let feedback = Arc::new(
            robot
                .publisher(
                    "/robot/move/_action/feedback",
                    "corridor_msgs/action/Move_FeedbackMessage",
                )
                .unwrap(),
        );
        let statuses = Arc::new(
            robot
                .publisher("/robot/move/_action/status", "action_msgs/msg/GoalStatusArray")
                .unwrap(),
        );
        let t = "corridor_msgs/action/Move";
        let _send = robot
            .serve(
                "/robot/move/_action/send_goal",
                &format!("{t}_SendGoal"),
                |req| {
                    let ok = req.path("goal.direction") == Some(&Value::Int(1));
                    Value::fields([("accepted", Value::Bool(ok))])
                },
                |_| {},
            )
            .unwrap();
        let (s, m, f, st) = (
            Arc::clone(&status),
            Arc::clone(&moved),
            Arc::clone(&feedback),
            Arc::clone(&statuses),
        );
        let _result = robot
            .serve(
                "/robot/move/_action/get_result",
                &format!("{t}_GetResult"),
                move |req| {
                    let code = s.load(Ordering::Relaxed);
                    let id = req.get("goal_id").cloned().unwrap_or_else(|| Value::fields([]));
                    f.publish(&Value::fields([
                        ("goal_id", id.clone()),
                        ("feedback", Value::fields([("progress", Value::Float(1.0))])),
                    ]))
                    .unwrap();
                    let one = Value::fields([
                        ("goal_info", Value::fields([("goal_id", id)])),
                        ("status", Value::Int(code)),
                    ]);
                    st.publish(&Value::fields([("status_list", Value::List(vec![one]))]))
                        .unwrap();
                    m.publish(&Value::fields([("data", Value::Bool(code == 4))])).unwrap();
                    Value::fields([
                        ("status", Value::Int(code)),
                        ("result", Value::fields([("moved", Value::Bool(code == 4))])),
                    ])
                },
                |_| {},
            )
            .unwrap();
        let _cancel = robot
            .serve(
                "/robot/move/_action/cancel_goal",
                "action_msgs/srv/CancelGoal",
                |_| Value::fields([]),
                |_| {},
            )
            .unwrap();
        // Wait until the world's session sees the robot's servers.
        assert!(sees_servers(&a, 3), "the robot's action servers are seen");
        let mut world = Ros2World::new(loaded, world_node).unwrap();
        world.reset(None);
        let done = world.step(&[Some(0)]);
        assert_eq!(done[0].action, ActionStatus::Finished);
        let start = Instant::now();
        while world.observe(0).atoms != vec![0] && start.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_millis(20));
        }
        assert_eq!(world.observe(0).atoms, vec![0], "the robot's state after the goal");
        status.store(9, Ordering::Relaxed);
        assert_eq!(world.step(&[Some(0)])[0].action, ActionStatus::Failed);
        status.store(6, Ordering::Relaxed);
        assert_eq!(world.step(&[Some(0)])[0].action, ActionStatus::Failed);
        let start = Instant::now();
        while world.counts().unknown_action_status < 2 && start.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_millis(20));
        }
        let counts = world.counts();
        // Status 9 refused twice: in the result and on the status topic.
        assert_eq!(counts.unknown_action_status, 2, "{counts:?}");
        assert_eq!(counts.timeouts, 0, "{counts:?}");
        assert!(counts.feedback >= 1, "{counts:?}");
    }

    const SERVICES: &str = r#"
timeout_ms = 3000
max_steps = 2
[zenoh]
connect = ["tcp/127.0.0.1:9"]

[[interfaces]]
name = "corridor_msgs/srv/Score"
file = "Score.srv"

[[action]]
name = "forward"
topic = "/robot/cmd"
type = "std_msgs/msg/Int32"
message = { data = 1 }

[reward]
service = "/robot/score"
type = "corridor_msgs/srv/Score"
field = "reward"

[end]
service = "/robot/score"
type = "corridor_msgs/srv/Score"
field = "done"
equals = true
"#;

    /// The reward and the episode's end from a service asked after each step;
    /// the step limit cuts the episode short.
    #[test]
    fn reward_and_end_come_from_a_service_after_each_step() {
        let dir = std::env::temp_dir().join(format!("learnpnp-ros2-services-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("Score.srv"), "int32 unused\n---\nfloat64 reward\nbool done\n").unwrap();
        std::fs::write(dir.join("m.toml"), SERVICES).unwrap();
        let loaded = mapping::load(&dir.join("m.toml")).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let registry = Arc::new(loaded.registry.clone());
        let (a, b) = loopback_pair();
        let world_node = Node::new(a.clone(), Arc::clone(&registry), 0, "/", "learnpnp_world").unwrap();
        let robot = Node::new(b, Arc::clone(&registry), 0, "/", "robot").unwrap();
        let asked = Arc::new(AtomicI64::new(0));
        let n = Arc::clone(&asked);
        let _score = robot
            .serve(
                "/robot/score",
                "corridor_msgs/srv/Score",
                move |_| {
                    // Asked twice per step (reward, end) and once at reset (end).
                    let k = n.fetch_add(1, Ordering::Relaxed);
                    Value::fields([("reward", Value::Float(-2.5)), ("done", Value::Bool(k >= 2))])
                },
                |_| {},
            )
            .unwrap();
        assert!(sees_servers(&a, 1), "the robot's service is seen");
        let mut world = Ros2World::new(loaded, world_node).unwrap();
        world.reset(None);
        assert!(!world.terminated() && !world.truncated());
        let step = world.step(&[Some(0)]);
        assert_eq!((step[0].reward, step[0].action), (-2.5, ActionStatus::Finished));
        assert!(world.terminated(), "the service said done");
        world.step(&[None]);
        assert!(world.truncated(), "max_steps = 2");
        assert_eq!(world.counts().timeouts, 0);
    }
}
