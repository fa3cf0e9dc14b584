//! What a bridge refused, by reason, and the file its host's supervisor
//! reads them from ([`learnpnp_system::hosts::report::LinkReport`], `link.json` in the host's work
//! directory). The bridge refuses what arrives of the wrong type, size, key,
//! sender or order itself ([`super::carry`](crate::carry), [`super::remote`](crate::remote)); the peers
//! refused at the TLS handshake and the messages host A's access control
//! denied are refused inside Zenoh, which says so only in its tracing
//! events: [`ZenohRefusals`](crate::refusals::ZenohRefusals) is a tracing layer that counts them.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use tracing::field::{Field, Visit};
use tracing::{Event, Level, Metadata, Subscriber};
use tracing_subscriber::layer::{Context, Layer};

/// Zenoh's refusals as its tracing events report them, counted.
///
/// Access control: every decision is a trace event, but so is each of the
/// nine decisions Zenoh makes in advance when it first sees a key on a link
/// (to cache them), whatever the peer then does; those follow the event
/// that announces the caching on the same thread at once and are not
/// counted. Counted are the peers' own messages and declarations denied
/// (ingress), and peers whose certificate names no subject of the policy
/// (everything they send is denied without a trace).
#[derive(Debug, Clone, Default)]
pub struct ZenohRefusals {
    tls_handshake: Arc<AtomicU64>,
    access_denied: Arc<AtomicU64>,
    /// Why the last peer was refused at the TLS handshake.
    last_handshake: Arc<std::sync::Mutex<Option<String>>>,
}

/// What Zenoh says when this host, connecting, refuses the other's
/// certificate (rustls's errors, as QUIC reports them).
const CERTIFICATE_REFUSED: [&str; 4] = [
    "invalid peer certificate",
    "UnknownIssuer",
    "BadSignature",
    "NotValidForName",
];

/// Where zenoh's QUIC listener reports a peer it refused at the TLS handshake.
const QUIC_TARGET: &str = "zenoh_link_commons::quic";

/// Where zenoh's access control reports its decisions.
const ACL_TARGET: &str = "zenoh::net::routing::interceptor::access_control";

/// Where zenoh reports each failed attempt to connect (at debug level: a
/// refused certificate is said only there).
const CONNECT_TARGET: &str = "zenoh::net::runtime::orchestrator";

/// The refusals of each kind printed to the log before they are only counted.
const LOGGED_REFUSALS: u64 = 20;

/// The decisions zenoh makes to cache a key's permissions.
const CACHED_DECISIONS: u8 = 9;

/// They follow the announcement within this.
const CACHING_WITHIN: std::time::Duration = std::time::Duration::from_millis(1);

thread_local! {
    /// Decisions still to come of a caching announced on this thread, and when it was.
    static CACHING: std::cell::Cell<(u8, Option<std::time::Instant>)> = const { std::cell::Cell::new((0, None)) };
}

impl ZenohRefusals {
    /// The counts so far: peers refused at the TLS handshake, and messages
    /// (or peers) denied by access control.
    pub fn counts(&self) -> (u64, u64) {
        (
            self.tls_handshake.load(Ordering::Relaxed),
            self.access_denied.load(Ordering::Relaxed),
        )
    }

    /// Why the last peer was refused at the TLS handshake, if one was.
    pub fn last_handshake_refusal(&self) -> Option<String> {
        self.last_handshake.lock().ok().and_then(|last| last.clone())
    }

    /// Counts a peer refused at the TLS handshake, for `reason`.
    fn handshake_refused(&self, reason: &str) {
        let n = self.tls_handshake.fetch_add(1, Ordering::Relaxed) + 1;
        if let Ok(mut last) = self.last_handshake.lock() {
            *last = Some(reason.to_string());
        }
        if n <= LOGGED_REFUSALS {
            eprintln!("bridge: refused a peer at the TLS handshake: {reason}");
        }
    }

    /// Installs the counter as the process's tracing subscriber (once, at start).
    pub fn install(&self) -> Result<(), String> {
        use tracing_subscriber::layer::SubscriberExt as _;
        let subscriber = tracing_subscriber::registry().with(self.clone());
        tracing::subscriber::set_global_default(subscriber).map_err(|e| e.to_string())
    }

    fn watched(metadata: &Metadata<'_>) -> bool {
        let target = metadata.target();
        (target.starts_with("zenoh") && *metadata.level() <= Level::WARN)
            || (target.starts_with(ACL_TARGET) && *metadata.level() >= Level::INFO)
            || (target == CONNECT_TARGET && *metadata.level() == Level::DEBUG)
    }

    /// Counts one of the access control's events.
    fn access_event(&self, message: &str) {
        if message.contains("caching permissions for") {
            CACHING.set((CACHED_DECISIONS, Some(std::time::Instant::now())));
            return;
        }
        let decision = message.contains(" is unauthorized to ") || message.contains(" is authorized to ");
        if decision && !message.starts_with("Using cached result") {
            let (left, at) = CACHING.get();
            if left > 0 && at.is_some_and(|t| t.elapsed() < CACHING_WITHIN) {
                CACHING.set((left - 1, at));
                return;
            }
        }
        let denied = message.contains(" is unauthorized to ") && message.contains("(ingress)");
        let stranger = message.contains("did not match any configured ACL subject");
        if denied || stranger {
            let n = self.access_denied.fetch_add(1, Ordering::Relaxed) + 1;
            if n <= LOGGED_REFUSALS {
                eprintln!("bridge: access control denied: {message}");
            }
        }
    }
}

/// The `message` field of an event, formatted.
#[derive(Default)]
struct Message(String);

impl Visit for Message {
    fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
        if field.name() == "message" {
            use std::fmt::Write as _;
            let _ = write!(self.0, "{value:?}");
        }
    }
}

impl<S: Subscriber> Layer<S> for ZenohRefusals {
    fn register_callsite(&self, metadata: &'static Metadata<'static>) -> tracing::subscriber::Interest {
        if Self::watched(metadata) {
            tracing::subscriber::Interest::always()
        } else {
            tracing::subscriber::Interest::never()
        }
    }

    fn enabled(&self, metadata: &Metadata<'_>, _: Context<'_, S>) -> bool {
        Self::watched(metadata)
    }

    fn on_event(&self, event: &Event<'_>, _: Context<'_, S>) {
        let mut message = Message::default();
        event.record(&mut message);
        let target = event.metadata().target();
        if target.starts_with(ACL_TARGET) {
            self.access_event(&message.0);
        } else if target.starts_with(QUIC_TARGET)
            && (message.0.contains("Cannot accept QUIC connection")
                || message.0.contains("increase the system open file limit"))
        {
            // The listener's accept failed: the TLS handshake (or reading the
            // peer's certificate) refused the peer.
            self.handshake_refused(message.0.split(" Hint").next().unwrap_or_default());
        } else if CERTIFICATE_REFUSED.iter().any(|m| message.0.contains(m)) {
            // Connecting, this host refused the other's certificate.
            self.handshake_refused(&message.0);
        } else if *event.metadata().level() == Level::DEBUG {
            // The connector's other news: not the log's business.
        } else {
            // Zenoh's other warnings and errors go to the bridge's log.
            eprintln!("bridge: zenoh: {}: {}", event.metadata().level(), message.0);
        }
    }
}
