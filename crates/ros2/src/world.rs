//! The world a mapping file makes of a ROS 2 robot: a
//! [`ServedWorld`](learnpnp_system::multiprocess::host::world::ServedWorld) whose state is the latest message on each mapped topic,
//! stepped in lock-step (each step waits for the robot's answer, so the run
//! goes at the robot's rate). Every wait for the robot (an answer, a
//! service's reply, a goal's result) keeps the host's house in slices
//! ([`Housekeeping`](learnpnp_system::multiprocess::host::world::Housekeeping)), so the world heartbeats however long the robot takes,
//! and is given up when the run stops.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use learnpnp_system::ipc::world::{ActionStatus, Vocabulary};
use learnpnp_system::multiprocess::host::world::{Housekeeping, Observation, ServedWorld, StepResult};
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
    /// Answers refused: for another command than the one awaited (or with
    /// no sequence number), when `[answer]` matches them by `sequence`.
    pub unmatched_answers: u64,
    /// Steps whose action failed (a timeout, a refused or failed goal, a
    /// command that could not be sent): the plan was told it failed.
    pub failed_actions: u64,
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
    /// The sequence number of the command whose answer is awaited
    /// (answers matched by `sequence`).
    expected: Option<i64>,
    /// The last sequence number answered.
    matched: Option<i64>,
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
    /// A message on a topic (and the field its sequence number goes in).
    Topic(Box<(Arc<Publisher>, Value, Option<String>)>),
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
    /// The goal's field its sequence number goes in.
    sequence: Option<String>,
}

/// A service polled after each step for a value.
struct Polled {
    client: Client,
    source: Source,
}

/// The answer a step or reset waits for.
#[derive(Debug, Clone, Copy)]
enum Awaited {
    /// Any answer after this many.
    After(u64),
    /// The answer carrying this sequence number.
    Sequence(i64),
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
    /// Commands numbered so far (answers matched by `sequence`).
    sequence: i64,
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
            let source = r.source.clone();
            let topic = r.source.topic.clone().unwrap_or_default();
            subscriptions.push(node.subscribe(&topic, &r.source.type_name, move |r| match r {
                Ok(Received { value, .. }) => {
                    sh.lock().reward += source.number(&value).unwrap_or(0.0);
                }
                Err(refusal) => sh.refuse(&refusal),
            })?);
        }
        if let Some(a) = &m.answer {
            let sh = Arc::clone(&shared);
            let sequence = a.sequence.clone();
            let topic = a.topic.clone();
            subscriptions.push(node.subscribe(&a.topic, &a.type_name, move |r| match r {
                Ok(Received { value, .. }) => {
                    let mut s = sh.lock();
                    s.answers += 1;
                    if let Some(field) = &sequence {
                        let number = value.path(field).and_then(Value::as_f64);
                        match (number, s.expected) {
                            (Some(n), Some(e)) if n == e as f64 => s.matched = Some(e),
                            (number, expected) => {
                                s.counts.unmatched_answers += 1;
                                drop(s);
                                let awaited = expected.map_or("none".to_string(), |e| e.to_string());
                                let carried = number.map_or("none".to_string(), |n| n.to_string());
                                eprintln!(
                                    "learnpnp-ros2-world: refused: an answer on '{topic}' for command {carried} (awaited: {awaited})"
                                );
                                return;
                            }
                        }
                    }
                    drop(s);
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
                    source: r.source.clone(),
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
            sequence: 0,
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

    /// Whether answers are matched to commands by their sequence number.
    fn matched(&self) -> bool {
        self.loaded
            .mapping
            .answer
            .as_ref()
            .is_some_and(|a| a.sequence.is_some())
    }

    /// Numbers the next command: the answer awaited from now on.
    fn next_sequence(&mut self) -> i64 {
        self.sequence += 1;
        self.shared.lock().expected = Some(self.sequence);
        self.sequence
    }

    /// Waits for the answer `awaited` (when the mapping has answers),
    /// keeping house: false if it did not come in time (counted) or the run
    /// stops.
    fn await_answer(&self, awaited: Awaited, house: &mut Housekeeping<'_>) -> bool {
        if self.loaded.mapping.answer.is_none() {
            return true;
        }
        let answered = |s: &State| match awaited {
            Awaited::After(before) => s.answers > before,
            Awaited::Sequence(n) => s.matched == Some(n),
        };
        let deadline = Instant::now() + self.timeout;
        let mut kept = Instant::now();
        let mut s = self.shared.lock();
        while !answered(&s) {
            if kept.elapsed() >= Housekeeping::EVERY {
                drop(s);
                if !house.keep() {
                    return false;
                }
                kept = Instant::now();
                s = self.shared.lock();
                continue;
            }
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
                return false;
            }
            s = self
                .shared
                .changed
                .wait_timeout(s, left.min(Housekeeping::EVERY))
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .0;
        }
        true
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
    fn run_goal(&self, clients: &ActionClients, goal: &Value, house: &mut Housekeeping<'_>) -> ActionStatus {
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
        match send_goal.call(&request, self.timeout, house) {
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
        match get_result.call(&Value::fields([("goal_id", id.clone())]), self.timeout, house) {
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
                if let Err(e) = cancel.call(&info, self.timeout, house) {
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
    fn take_reward(&self, house: &mut Housekeeping<'_>) -> f64 {
        let mut reward = self.loaded.mapping.step_reward + std::mem::take(&mut self.shared.lock().reward);
        if let Some(p) = &self.reward_service {
            match p.client.call(&Value::fields([]), self.timeout, house) {
                Ok(v) => reward += p.source.number(&v).unwrap_or(0.0),
                Err(e) => self.failed("reward service", &e),
            }
        }
        reward
    }

    fn poll_end(&mut self, house: &mut Housekeeping<'_>) {
        if let Some((client, _)) = &self.end_service {
            match client.call(&Value::fields([]), self.timeout, house) {
                Ok(v) => self.end_value = Some(v),
                Err(e) => self.failed("end service", &e),
            }
        }
    }
}

/// `message` with sequence number `n` in its field, if `numbered`.
fn with_number<'v>(message: &'v Value, numbered: Option<(&str, i64)>) -> Cow<'v, Value> {
    match numbered {
        Some((field, n)) => {
            let mut v = message.clone();
            v.set_path(field, Value::Int(n));
            Cow::Owned(v)
        }
        None => Cow::Borrowed(message),
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
        return Ok(Command::Topic(Box::new((publisher, message, a.sequence.clone()))));
    }
    let action = a.action.clone().unwrap_or_default();
    if let Some(c) = made.clients.get(&node.qualify(&action)) {
        return Ok(Command::Action(Box::new(Goal {
            clients: Arc::clone(c),
            goal: message,
            sequence: a.sequence.clone(),
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
        sequence: a.sequence.clone(),
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

    fn reset(&mut self, _seed: Option<u64>, house: &mut Housekeeping<'_>) {
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
            while let Err(e) = reset.call(&request, self.timeout, house) {
                self.failed("reset", &e);
                if matches!(e, Ros2Error::GivenUp { .. }) {
                    return;
                }
                tries += 1;
                if tries == 5 {
                    // The robot is gone: end the world so that the supervisor sees it.
                    eprintln!("error: learnpnp-ros2-world: the robot's reset service did not answer {tries} times");
                    std::process::exit(1);
                }
            }
        }
        // Answers matched by sequence number: the reset service's reply
        // (matched by its request) is the reset's answer.
        if !self.matched() {
            self.await_answer(Awaited::After(before), house);
        }
        self.shared.lock().reward = 0.0;
        self.poll_end(house);
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
            .map(|f| self.latest(&f.source).and_then(|v| f.source.number(&v)).unwrap_or(0.0))
            .collect();
        Observation { atoms, fluents }
    }

    fn step(&mut self, actions: &[Option<usize>], house: &mut Housekeeping<'_>) -> Vec<StepResult> {
        self.steps += 1;
        self.shared.lock().counts.steps += 1;
        let index = actions.first().copied().flatten().filter(|&a| a < self.commands.len());
        // The command's sequence number, written into its field, when
        // answers are matched by it; else any answer after the command's.
        let field = index.and_then(|a| match &self.commands[a] {
            Command::Topic(t) => t.2.clone(),
            Command::Action(g) => g.sequence.clone(),
        });
        let (awaited, numbered) = match &field {
            Some(field) => {
                let n = self.next_sequence();
                (Some(Awaited::Sequence(n)), Some((field.as_str(), n)))
            }
            // A goal's result, matched by its request, is its answer.
            None if self.matched() => (None, None),
            None => (Some(Awaited::After(self.answers())), None),
        };
        let status = match index.map(|a| &self.commands[a]) {
            None => ActionStatus::None,
            Some(Command::Topic(t)) => match t.0.publish(&with_number(&t.1, numbered)) {
                Ok(()) => ActionStatus::Finished,
                Err(e) => {
                    self.failed("command", &e);
                    ActionStatus::Failed
                }
            },
            Some(Command::Action(g)) => self.run_goal(&g.clients, &with_number(&g.goal, numbered), house),
        };
        // An answer that does not come in time fails the action; a failed
        // action waits for nothing more.
        let status = match (status, awaited) {
            (ActionStatus::Finished, Some(awaited)) if !self.await_answer(awaited, house) => ActionStatus::Failed,
            (status, _) => status,
        };
        if status == ActionStatus::Failed {
            self.shared.lock().counts.failed_actions += 1;
        }
        let reward = self.take_reward(house);
        self.poll_end(house);
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
        world.reset(None, &mut Housekeeping::none());
        let done = world.step(&[Some(0)], &mut Housekeeping::none());
        assert_eq!(done[0].action, ActionStatus::Finished);
        let start = Instant::now();
        while world.observe(0).atoms != vec![0] && start.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_millis(20));
        }
        assert_eq!(world.observe(0).atoms, vec![0], "the robot's state after the goal");
        status.store(9, Ordering::Relaxed);
        assert_eq!(
            world.step(&[Some(0)], &mut Housekeeping::none())[0].action,
            ActionStatus::Failed
        );
        status.store(6, Ordering::Relaxed);
        assert_eq!(
            world.step(&[Some(0)], &mut Housekeeping::none())[0].action,
            ActionStatus::Failed
        );
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
        world.reset(None, &mut Housekeeping::none());
        assert!(!world.terminated() && !world.truncated());
        let step = world.step(&[Some(0)], &mut Housekeeping::none());
        assert_eq!((step[0].reward, step[0].action), (-2.5, ActionStatus::Finished));
        assert!(world.terminated(), "the service said done");
        world.step(&[None], &mut Housekeeping::none());
        assert!(world.truncated(), "max_steps = 2");
        assert_eq!(world.counts().timeouts, 0);
    }

    const MATCHED: &str = r#"
timeout_ms = 400
[zenoh]
connect = ["tcp/127.0.0.1:9"]

[[interfaces]]
name = "corridor_msgs/msg/Cmd"
file = "Cmd.msg"

[[interfaces]]
name = "corridor_msgs/msg/Done"
file = "Done.msg"

[[action]]
name = "forward"
topic = "/robot/cmd"
type = "corridor_msgs/msg/Cmd"
message = { direction = 1 }
sequence = "seq"

[answer]
topic = "/robot/done"
type = "corridor_msgs/msg/Done"
sequence = "command"
"#;

    /// Each command carries its sequence number; the robot's answer is taken
    /// only if it carries it back: a stale answer is refused and counted, and
    /// a step with no matching answer times out as a failed action.
    #[test]
    fn answers_are_matched_to_their_commands_and_a_step_without_one_fails() {
        let dir = std::env::temp_dir().join(format!("learnpnp-ros2-matched-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("Cmd.msg"), "int32 direction\nint64 seq\n").unwrap();
        std::fs::write(dir.join("Done.msg"), "int64 command\n").unwrap();
        std::fs::write(dir.join("m.toml"), MATCHED).unwrap();
        let loaded = mapping::load(&dir.join("m.toml")).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let registry = Arc::new(loaded.registry.clone());
        let (a, b) = loopback_pair();
        let world_node = Node::new(a, Arc::clone(&registry), 0, "/", "learnpnp_world").unwrap();
        let robot = Node::new(b, Arc::clone(&registry), 0, "/", "robot").unwrap();
        let done = Arc::new(robot.publisher("/robot/done", "corridor_msgs/msg/Done").unwrap());
        // 0: the robot answers with the command's number; 1: with the one
        // before only (a late answer of the previous step); 2: both, the stale one first.
        let mode = Arc::new(AtomicI64::new(0));
        let (m, d) = (Arc::clone(&mode), Arc::clone(&done));
        let _commands = robot
            .subscribe("/robot/cmd", "corridor_msgs/msg/Cmd", move |r| {
                let Ok(Received { value, .. }) = r else { return };
                let seq = value.get("seq").and_then(Value::as_f64).unwrap() as i64;
                let answer = |n: i64| d.publish(&Value::fields([("command", Value::Int(n))])).unwrap();
                match m.load(Ordering::Relaxed) {
                    0 => answer(seq),
                    1 => answer(seq - 1),
                    _ => {
                        answer(seq - 1);
                        answer(seq);
                    }
                }
            })
            .unwrap();
        let mut world = Ros2World::new(loaded, world_node).unwrap();
        world.reset(None, &mut Housekeeping::none());
        // Until the two sessions see each other's subscriptions, commands
        // and answers are lost (timeouts).
        let start = Instant::now();
        while world.step(&[Some(0)], &mut Housekeeping::none())[0].action != ActionStatus::Finished {
            assert!(start.elapsed() < Duration::from_secs(30), "{:?}", world.counts());
        }
        let before = world.counts();
        mode.store(2, Ordering::Relaxed);
        assert_eq!(
            world.step(&[Some(0)], &mut Housekeeping::none())[0].action,
            ActionStatus::Finished
        );
        mode.store(1, Ordering::Relaxed);
        assert_eq!(
            world.step(&[Some(0)], &mut Housekeeping::none())[0].action,
            ActionStatus::Failed,
            "no answer of its own"
        );
        mode.store(0, Ordering::Relaxed);
        assert_eq!(
            world.step(&[Some(0)], &mut Housekeeping::none())[0].action,
            ActionStatus::Finished
        );
        let after = world.counts();
        assert_eq!(after.unmatched_answers - before.unmatched_answers, 2, "{after:?}");
        assert_eq!(after.timeouts - before.timeouts, 1, "{after:?}");
        assert_eq!(after.failed_actions - before.failed_actions, 1, "{after:?}");
        // A step whose answer does not come keeps the host's house all the
        // while it waits (400 ms, in slices of Housekeeping::EVERY) ...
        mode.store(1, Ordering::Relaxed);
        let mut kept = 0;
        let mut count = || {
            kept += 1;
            true
        };
        let step = world.step(&[Some(0)], &mut Housekeeping::new(&mut count));
        assert_eq!(step[0].action, ActionStatus::Failed);
        assert!(kept >= 2, "housekeeping {kept} times in a wait of 400 ms");
        let waited = world.counts();
        assert_eq!(waited.timeouts - after.timeouts, 1, "{waited:?}");
        // ... and gives the wait up once the run stops: no timeout.
        let mut stopping = || false;
        let step = world.step(&[Some(0)], &mut Housekeeping::new(&mut stopping));
        assert_eq!(step[0].action, ActionStatus::Failed);
        assert_eq!(world.counts().timeouts, waited.timeouts, "{:?}", world.counts());
    }
}
