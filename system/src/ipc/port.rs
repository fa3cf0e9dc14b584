//! What every port of a run is made of: the iceoryx2 service variant
//! ([`Ipc`](crate::ipc::port::Ipc)), publishers and subscribers of it, and the error of opening or
//! using one ([`IpcError`](crate::ipc::port::IpcError)). [`super::services`](crate::ipc::services) opens the ports,
//! [`super::wait`](crate::ipc::wait) waits on them.

use std::fmt::Debug;

use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::ipc;

/// The iceoryx2 service variant of every port: inter-process, single-threaded ports.
pub type Ipc = ipc::Service;

/// A publisher of `T`.
pub type Pub<T> = Publisher<Ipc, T, ()>;
/// A subscriber of `T`.
pub type Sub<T> = Subscriber<Ipc, T, ()>;

/// Why a port cannot be opened or used.
#[derive(Debug, thiserror::Error)]
pub enum IpcError {
    /// An iceoryx2 operation failed.
    #[error("{operation}: {detail}")]
    Iceoryx {
        /// What was being done (names the service).
        operation: String,
        /// iceoryx2's error.
        detail: String,
    },
    /// The namespace is unusable.
    #[error(transparent)]
    Namespace(#[from] super::namespace::NamespaceError),
}

/// Wraps an iceoryx2 error with what was being done.
pub fn fail<E: Debug>(operation: impl Into<String>) -> impl FnOnce(E) -> IpcError {
    let operation = operation.into();
    move |e| IpcError::Iceoryx {
        operation,
        detail: format!("{e:?}"),
    }
}
