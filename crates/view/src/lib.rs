//! The live view of a learnpnp run: the feed ([`learnpnp_feed`]) served over
//! the Foxglove WebSocket protocol with a page of its own, recorded to MCAP,
//! and written as PNP's monitor line.
//!
//! [`View::start`] starts what [`ViewOptions`] asks for; the view is a
//! [`FeedSink`]: publish records to it from any thread (a
//! `WatchedLearner` of the `learnpnp` crate does so for a learner). Publishing
//! never blocks: a record goes into a bounded queue (dropped and counted when
//! it is full), and one thread of the view, waking every [`TICK`] (or sooner
//! once the queue is half full, so a fast learner loses nothing), logs each
//! record queued since on its channel, encoding it as JSON when something
//! takes it (a client of the channel, the recording). The
//! view's threads run as background threads ([`run_in_background`]): waking,
//! they do not preempt a learner.
//!
//! - **WebSocket and page**: the Foxglove SDK's server (`foxglove` crate)
//!   listens on an ephemeral loopback port; the view's own address (loopback,
//!   port [`DEFAULT_PORT`] unless told otherwise) takes HTTP: a WebSocket
//!   upgrade (subprotocol `foxglove.sdk.v1` or `foxglove.sdk.v1.1`) is passed
//!   on to the SDK's server, any other GET serves the page (`/`, `/app.js`,
//!   `/mcap.js`, `/style.css`, embedded in the binary) and, when the view
//!   replays a recording, the file at `/recording.mcap`.
//! - **Channels**: one per kind of record, named by
//!   [`FeedEvent::channel`], with the record's JSON schema; a message is the
//!   record itself as JSON (without the enum's tag: the channel says which
//!   kind it is; [`FeedEvent::from_payload`] reads it back). A client that
//!   subscribes to `/learnpnp/plan` or `/learnpnp/curve` is sent the plans and
//!   the curve published so far, so a page opened mid-run can draw them.
//! - **The page's bundle**: [`BUNDLE_CHANNEL`] carries, once every [`BUNDLE_EVERY`], for
//!   each agent, what the page draws of the records that come at the run's
//!   pace (the latest marking, each choice point's latest choice, counts, the
//!   episodes' returns) and the processes' latest health and latency, so that
//!   a page following a fast run is sent one message a second rather than
//!   every record and a message per process. It is built only while a
//!   client subscribes to it, and not recorded.
//! - **Plans**: a plan is logged when it is new or changed; an agent
//!   process's resending of an unchanged plan (for a view started late) is
//!   not passed on, since a client is sent the plans kept when it subscribes.
//! - **MCAP**: the same channels, written by the SDK's writer to `FILE.part`
//!   and renamed to `FILE` when the view closes (so a file under the final
//!   name is complete). Chunks are not compressed, so that the page's small
//!   reader can read them without a decompressor.
//! - **PNP's monitor line**: the root plan's markings of run 0's agent 0 (a
//!   PNP observer watches one plan); see [`PNP_MONITOR_PORT`].

#![deny(missing_docs)]

mod bundle;
mod http;
mod pnp_monitor;

use std::collections::HashMap;
use std::io::{BufWriter, Write};
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crossbeam::channel::{Receiver, Sender, TryRecvError, TrySendError};
use foxglove::websocket::{ChannelView, Client, ServerListener};
use foxglove::{ChannelBuilder, Context, McapWriteOptions, McapWriter, McapWriterHandle, RawChannel, Schema, SinkId};
use learnpnp_feed::{CHANNELS, FeedEvent, FeedSink, MarkingSample, PlanShape, Source};

pub use bundle::BUNDLE_CHANNEL;
use bundle::{BUNDLE_SCHEMA, Bundle};
pub use pnp_monitor::PNP_MONITOR_PORT;

/// The view's default port (Foxglove's usual WebSocket port).
pub const DEFAULT_PORT: u16 = 8765;

/// The records a view holds before it drops what is published (see [`View::dropped`]).
pub const DEFAULT_QUEUE: usize = 8192;

/// The kinds of record the view reads (their indexes in [`CHANNELS`]).
const PLAN: usize = 0;
const MARKING: usize = 1;
const CHOICE: usize = 2;
const EPISODE: usize = 4;
const CURVE: usize = 5;
const HEALTH: usize = 6;
const LATENCY: usize = 7;

/// The agent whose markings PNP's monitor line follows (a PNP observer watches one plan).
const MONITORED: Source = Source { run: 0, agent: 0 };

/// The messages the SDK's server holds for a slow client before it drops
/// the oldest (its default is 1024: a burst of choices would push out a curve point).
const CLIENT_BACKLOG: usize = 65_536;

/// How long a closing view lets its clients receive its last records.
const CLOSE_GRACE: Duration = Duration::from_millis(200);

/// How often the view's thread logs what has been published since it last
/// woke (so a client is sent bursts, at most this much late, rather than a
/// write per record).
pub const TICK: Duration = Duration::from_millis(20);

/// How often the page's bundle ([`BUNDLE_CHANNEL`]) is sent: as often as the
/// page redraws live (once a second), since a bundle holds the latest of
/// what the page draws and counts the rest.
pub const BUNDLE_EVERY: Duration = Duration::from_millis(1000);

/// The most curve points kept for clients that connect mid-run.
const CURVE_KEPT: usize = 100_000;

/// The view's default address: loopback, [`DEFAULT_PORT`].
pub const fn default_address() -> SocketAddr {
    SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), DEFAULT_PORT)
}

/// PNP's monitor line's default address: loopback, [`PNP_MONITOR_PORT`].
pub const fn default_pnp_monitor_address() -> SocketAddr {
    SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), PNP_MONITOR_PORT)
}

/// Makes the calling thread a background thread: on Linux it is scheduled
/// as `SCHED_BATCH`, so that waking it does not preempt a running thread (a
/// learner's); it still gets its fair share of the CPU. The view's own threads
/// call it; a process that only serves a view calls it before starting one.
pub fn run_in_background() {
    #[cfg(target_os = "linux")]
    {
        let param = libc::sched_param { sched_priority: 0 };
        // SAFETY: `param` is a valid `sched_param` that outlives the call;
        // pid 0 is the calling thread. A refusal leaves the thread as it was.
        let _ = unsafe { libc::sched_setscheduler(0, libc::SCHED_BATCH, &param) };
    }
}

/// What a view serves and writes; each part is off when `None`.
#[derive(Debug, Clone)]
pub struct ViewOptions {
    /// The page and the Foxglove WebSocket protocol, on this address (port 0: any free port).
    pub address: Option<SocketAddr>,
    /// An MCAP recording of every channel, written to this file.
    pub record_mcap: Option<PathBuf>,
    /// PNP's monitor line, on this address.
    pub pnp_monitor: Option<SocketAddr>,
    /// A recording the page replays, served at `/recording.mcap`.
    pub replay: Option<PathBuf>,
    /// The records held before publishing drops them.
    pub queue: usize,
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            address: None,
            record_mcap: None,
            pnp_monitor: None,
            replay: None,
            queue: DEFAULT_QUEUE,
        }
    }
}

/// Why a view could not start or close.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// A socket or file could not be opened, written or renamed.
    #[error("{what}: {source}")]
    Io {
        /// What was being done.
        what: String,
        /// Why it failed.
        #[source]
        source: std::io::Error,
    },
    /// The Foxglove SDK refused (a channel, the server, the MCAP writer).
    #[error("{what}: {source}")]
    Foxglove {
        /// What was being done.
        what: String,
        /// Why it failed.
        #[source]
        source: foxglove::FoxgloveError,
    },
    /// The view's thread stopped abnormally.
    #[error("the view's thread panicked")]
    Thread,
}

fn io_error(what: impl Into<String>) -> impl FnOnce(std::io::Error) -> ViewError {
    let what = what.into();
    move |source| ViewError::Io { what, source }
}

fn fox_error(what: impl Into<String>) -> impl FnOnce(foxglove::FoxgloveError) -> ViewError {
    let what = what.into();
    move |source| ViewError::Foxglove { what, source }
}

/// What the view's thread is asked to do.
enum Command {
    /// Log a record.
    Publish(FeedEvent),
    /// Log a record already encoded: its kind and its channel's payload.
    Payload(usize, Vec<u8>),
    /// Finish.
    Close,
}

/// A client that subscribed to a channel whose past the view keeps: the
/// channel's index in [`CHANNELS`] and the client's sink.
type Resend = (usize, SinkId);

/// Tells the view's thread when a client subscribes to a channel whose past it keeps.
struct Subscriptions {
    /// Unbounded, apart from the records' queue: a late client's plan is never
    /// dropped because the records fill their queue.
    resends: Sender<Resend>,
}

impl ServerListener for Subscriptions {
    fn on_subscribe(&self, client: Client, channel: ChannelView) {
        let kind = CHANNELS.iter().position(|c| *c == channel.topic());
        if let (Some(kind @ (PLAN | CURVE)), Some(sink)) = (kind, client.sink_id()) {
            // Fails only once the view's thread has finished.
            let _ = self.resends.send((kind, sink));
        }
    }
}

/// A running view: a [`FeedSink`] serving and recording what is published to it.
///
/// Closing it ([`View::close`], or dropping it) stops the servers and
/// completes the recording.
pub struct View {
    commands: Sender<Command>,
    dropped: AtomicU64,
    address: Option<SocketAddr>,
    pnp_monitor: Option<SocketAddr>,
    worker: Option<JoinHandle<Result<Counts, ViewError>>>,
    server: Option<foxglove::WebSocketServerHandle>,
    runtime: Option<tokio::runtime::Runtime>,
}

impl std::fmt::Debug for View {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("View")
            .field("address", &self.address)
            .field("pnp_monitor", &self.pnp_monitor)
            .field("dropped", &self.dropped())
            .finish_non_exhaustive()
    }
}

/// How many records a view logged on each channel, in the order of [`CHANNELS`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts(pub [u64; CHANNELS.len()]);

impl Counts {
    /// The records logged on `channel`; 0 for a topic that is not the feed's.
    pub fn of(&self, channel: &str) -> u64 {
        CHANNELS.iter().position(|c| *c == channel).map_or(0, |i| self.0[i])
    }
}

impl View {
    /// Starts what `options` asks for (nothing listens unless asked).
    pub fn start(options: ViewOptions) -> Result<View, ViewError> {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .thread_name("learnpnp-view")
            .on_thread_start(run_in_background)
            .enable_all()
            .build()
            .map_err(io_error("starting the view's runtime"))?;
        let context = Context::new();
        let channels = CHANNELS
            .iter()
            .zip(learnpnp_feed::channel_schemas())
            .map(|(topic, (_, name, schema))| {
                ChannelBuilder::new(*topic)
                    .context(&context)
                    .message_encoding("json")
                    .schema(Schema::new(name, "jsonschema", schema.into_bytes()))
                    .build_raw()
                    .map_err(fox_error(format!("creating channel {topic}")))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let bundle = ChannelBuilder::new(BUNDLE_CHANNEL)
            .context(&context)
            .message_encoding("json")
            .schema(Schema::new("Bundle", "jsonschema", BUNDLE_SCHEMA.as_bytes().to_vec()))
            .build_raw()
            .map_err(fox_error(format!("creating channel {BUNDLE_CHANNEL}")))?;
        let (commands, queue) = crossbeam::channel::bounded(options.queue.max(1));
        let (resends, resend_queue) = crossbeam::channel::unbounded();
        let mut view = View {
            commands: commands.clone(),
            dropped: AtomicU64::new(0),
            address: None,
            pnp_monitor: None,
            worker: None,
            server: None,
            runtime: None,
        };
        if let Some(address) = options.address {
            let server = runtime
                .block_on(
                    foxglove::WebSocketServer::new()
                        .name("learnpnp")
                        .message_backlog_size(CLIENT_BACKLOG)
                        .context(&context)
                        .bind(Ipv4Addr::LOCALHOST.to_string(), 0)
                        .listener(Arc::new(Subscriptions { resends }))
                        .tokio_runtime(runtime.handle())
                        .start(),
                )
                .map_err(fox_error("starting the Foxglove WebSocket server"))?;
            let upstream = SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), server.port());
            view.server = Some(server);
            let listener = runtime
                .block_on(tokio::net::TcpListener::bind(address))
                .map_err(io_error(format!("listening on {address}")))?;
            view.address = Some(listener.local_addr().map_err(io_error("reading the view's address"))?);
            let front = Arc::new(http::Front {
                upstream,
                recording: options.replay.clone(),
            });
            runtime.spawn(http::serve(listener, front));
        }
        let clients = pnp_monitor::Clients::default();
        if let Some(address) = options.pnp_monitor {
            let listener = runtime
                .block_on(tokio::net::TcpListener::bind(address))
                .map_err(io_error(format!("listening on {address}")))?;
            view.pnp_monitor = Some(
                listener
                    .local_addr()
                    .map_err(io_error("reading the monitor's address"))?,
            );
            runtime.spawn(pnp_monitor::accept(listener, clients.clone()));
        }
        let recording = match &options.record_mcap {
            Some(file) => Some(Recording::start(file, &context)?),
            None => None,
        };
        let worker = Worker {
            channels,
            bundle: Bundle::new(bundle),
            plans: HashMap::new(),
            curve: Vec::new(),
            clients,
            counts: Counts::default(),
            _context: context,
        };
        view.worker = Some(
            std::thread::Builder::new()
                .name("learnpnp-view".into())
                .spawn(move || worker.run(&queue, &resend_queue, recording))
                .map_err(io_error("starting the view's thread"))?,
        );
        view.runtime = Some(runtime);
        Ok(view)
    }

    /// The address of the page and the WebSocket protocol, if served.
    pub fn address(&self) -> Option<SocketAddr> {
        self.address
    }

    /// The address of PNP's monitor line, if served.
    pub fn pnp_monitor_address(&self) -> Option<SocketAddr> {
        self.pnp_monitor
    }

    /// How many records were dropped because the view could not keep up.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }

    /// Stops serving, completes the recording, and returns what was logged on each channel.
    pub fn close(mut self) -> Result<Counts, ViewError> {
        self.shutdown()
    }

    fn shutdown(&mut self) -> Result<Counts, ViewError> {
        let counts = match self.worker.take() {
            Some(worker) => {
                // The queue may be full: this one waits for room, the worker drains it.
                let _ = self.commands.send(Command::Close);
                worker.join().map_err(|_| ViewError::Thread)
            }
            None => Ok(Ok(Counts::default())),
        };
        if let Some(server) = self.server.take() {
            // Stopping, the SDK's server drops what its clients have not been
            // sent yet: they are given a moment for the view's last records.
            if server.client_count() > 0 {
                std::thread::sleep(CLOSE_GRACE);
            }
            server.stop().wait_blocking();
        }
        if let Some(runtime) = self.runtime.take() {
            runtime.shutdown_background();
        }
        counts?
    }
}

impl Drop for View {
    fn drop(&mut self) {
        let _ = self.shutdown();
    }
}

impl View {
    /// Queues `command` for the view's thread, or counts it dropped.
    fn queue(&self, command: Command) {
        if let Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) = self.commands.try_send(command) {
            self.dropped.fetch_add(1, Ordering::Relaxed);
        }
        // Half full: the worker is woken before its tick (no system call unless it is asleep).
        if self.commands.len() >= self.commands.capacity().unwrap_or(usize::MAX) / 2
            && let Some(worker) = &self.worker
        {
            worker.thread().unpark();
        }
    }
}

impl FeedSink for View {
    fn publish(&self, event: &FeedEvent) {
        self.queue(Command::Publish(event.clone()));
    }

    /// Passes the payload on as it is (the view's thread does not encode it again).
    fn publish_payload(&self, kind: usize, payload: &[u8]) {
        if kind < CHANNELS.len() {
            self.queue(Command::Payload(kind, payload.to_vec()));
        } else {
            self.dropped.fetch_add(1, Ordering::Relaxed);
        }
    }
}

/// The MCAP file being written.
struct Recording {
    handle: McapWriterHandle<BufWriter<std::fs::File>>,
    part: PathBuf,
    file: PathBuf,
}

impl Recording {
    fn start(file: &Path, context: &Arc<Context>) -> Result<Recording, ViewError> {
        let mut part = file.as_os_str().to_owned();
        part.push(".part");
        let part = PathBuf::from(part);
        let out = std::fs::File::create(&part).map_err(io_error(format!("creating {}", part.display())))?;
        let handle = McapWriter::with_options(McapWriteOptions::new().compression(None))
            .context(context)
            .channel_filter_fn(|channel| channel.topic() != BUNDLE_CHANNEL)
            .create(BufWriter::new(out))
            .map_err(fox_error(format!("starting the MCAP recording {}", part.display())))?;
        Ok(Recording {
            handle,
            part,
            file: file.to_owned(),
        })
    }

    fn finish(self) -> Result<(), ViewError> {
        let what = format!("completing the MCAP recording {}", self.part.display());
        let mut out = self.handle.close().map_err(fox_error(what.clone()))?;
        out.flush().map_err(io_error(what.clone()))?;
        out.get_ref().sync_all().map_err(io_error(what))?;
        std::fs::rename(&self.part, &self.file).map_err(io_error(format!(
            "renaming {} to {}",
            self.part.display(),
            self.file.display()
        )))
    }
}

/// The view's thread: encodes and logs records, keeps what late clients are sent.
struct Worker {
    channels: Vec<Arc<RawChannel>>,
    bundle: Bundle,
    /// The latest plan of each agent, as JSON, and its monitor line's format.
    plans: HashMap<Source, (Vec<u8>, pnp_monitor::LineFormat)>,
    /// The curve so far, as JSON.
    curve: Vec<Vec<u8>>,
    clients: pnp_monitor::Clients,
    counts: Counts,
    /// Keeps the channels' context (and so its sinks) alive.
    _context: Arc<Context>,
}

impl Worker {
    fn run(
        mut self,
        queue: &Receiver<Command>,
        resends: &Receiver<Resend>,
        recording: Option<Recording>,
    ) -> Result<Counts, ViewError> {
        run_in_background();
        let mut next = Instant::now() + TICK;
        let mut next_bundle = Instant::now() + BUNDLE_EVERY;
        'ticks: loop {
            // Until the tick, unless a publisher finds the queue half full.
            std::thread::park_timeout(next.saturating_duration_since(Instant::now()));
            if Instant::now() >= next {
                next = (next + TICK).max(Instant::now());
            }
            for (kind, sink) in resends.try_iter() {
                self.resend(kind, sink);
            }
            // What was queued when the pass began (at least one look, which
            // sees a closed queue): a learner that outpaces the view cannot
            // keep it in one pass, nor grow one bundle without bound.
            for _ in 0..queue.len().max(1) {
                match queue.try_recv() {
                    Ok(Command::Publish(event)) => self.log_event(&event),
                    Ok(Command::Payload(kind, json)) => self.log(kind, json),
                    Ok(Command::Close) | Err(TryRecvError::Disconnected) => break 'ticks,
                    Err(TryRecvError::Empty) => break,
                }
            }
            if Instant::now() >= next_bundle {
                self.bundle.send();
                next_bundle = (next_bundle + BUNDLE_EVERY).max(Instant::now());
            }
        }
        self.bundle.send();
        self.bundle.channel.close();
        for channel in &self.channels {
            channel.close();
        }
        if let Some(recording) = recording {
            recording.finish()?;
        }
        Ok(self.counts)
    }

    /// Sends the kept records of channel `kind` (the plans or the curve) to one client.
    fn resend(&self, kind: usize, sink: SinkId) {
        let kept: Vec<&Vec<u8>> = match kind {
            PLAN => self.plans.values().map(|(json, _)| json).collect(),
            _ => self.curve.iter().collect(),
        };
        for json in kept {
            self.channels[kind].log_to_sink(json, Some(sink));
        }
    }

    /// Logs the payload `json` of a record of kind `kind` on its channel;
    /// keeps the plans and the curve for late clients, and writes PNP's
    /// monitor line. Only what needs a record's fields reads them: a plan, and
    /// a marking while the monitor line has clients.
    fn log(&mut self, kind: usize, json: Vec<u8>) {
        self.counts.0[kind] += 1;
        if kind == PLAN {
            self.log_plan(json);
            return;
        }
        self.channels[kind].log(&json);
        match kind {
            MARKING => self.bundle.add_marking(&json),
            CHOICE => self.bundle.add_choice(&json),
            EPISODE => self.bundle.add_episode(&json),
            HEALTH => self.bundle.add_health(&json),
            LATENCY => self.bundle.add_latency(&json),
            _ => {}
        }
        match kind {
            CURVE if self.curve.len() < CURVE_KEPT => self.curve.push(json),
            MARKING if self.monitored() => {
                // PNP's observer watches one plan: the first agent's root plan of the first run.
                if let Ok(marking) = serde_json::from_slice::<MarkingSample>(&json)
                    && marking.source == MONITORED
                    && marking.sub_plan.is_none()
                    && let Some((_, format)) = self.plans.get(&marking.source)
                {
                    pnp_monitor::broadcast(&self.clients, &format.line(&marking));
                }
            }
            _ => {}
        }
    }

    /// Logs a record published in the view's process. It is encoded only
    /// when something takes it as JSON (a client of its channel, the
    /// recording, the plans and the curve kept, PNP's monitor line); the
    /// page's bundle otherwise keeps it as it is.
    fn log_event(&mut self, event: &FeedEvent) {
        let kind = event.kind();
        let wanted =
            self.channels[kind].has_sinks() || matches!(kind, PLAN | CURVE) || (kind == MARKING && self.monitored());
        if wanted {
            if let Ok(json) = event.payload_json() {
                self.log(kind, json);
            }
        } else {
            self.counts.0[kind] += 1;
            self.bundle.add_event(event);
        }
    }

    /// Whether PNP's monitor line has clients.
    fn monitored(&self) -> bool {
        !self.clients.lock().unwrap_or_else(PoisonError::into_inner).is_empty()
    }

    /// Logs a plan and keeps it, unless it is the plan already kept for its
    /// agent: an agent process sends its plan again every second for a view
    /// started late, and every client that subscribes is sent the plans kept,
    /// so a plan sent again unchanged would tell no client anything.
    fn log_plan(&mut self, json: Vec<u8>) {
        let Ok(shape) = serde_json::from_slice::<PlanShape>(&json) else {
            self.channels[PLAN].log(&json);
            return;
        };
        if self.plans.get(&shape.source).is_some_and(|(kept, _)| *kept == json) {
            return;
        }
        self.channels[PLAN].log(&json);
        self.plans
            .insert(shape.source.clone(), (json, pnp_monitor::LineFormat::new(&shape)));
    }
}
