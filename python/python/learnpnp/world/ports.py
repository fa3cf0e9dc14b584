"""The world process's iceoryx2 ports on the run's services, and how it waits.

The supervisor creates every service of the run before it starts the world
(``shm_layouts/README.md``, "A world in its own process"); the world opens
them with the same limits as requirements, so a world started outside a run
fails at once instead of waiting for agents that never come.

iceoryx2's Python bindings carry no annotations, so its types (``iox.Node``,
``iox.Publisher``, ...) name what each value is but read as ``Any`` to mypy.
"""

from __future__ import annotations

import ctypes
import os
import time
from typing import Iterable, List, Optional, Tuple, Type, TypeVar, Union

try:
    import iceoryx2 as iox
except ImportError as error:  # pragma: no cover - depends on the installation
    raise ImportError(
        "learnpnp.world needs the iceoryx2 package: pip install iceoryx2==0.10.0 "
        "(or pip install 'learnpnp[world]')"
    ) from error

from .layouts import AgentReport, Control, Heartbeat, WorldCommand, WorldSnapshot, WorldVocabulary

#: A message type (one of ``layouts``' structures).
_Message = TypeVar("_Message", bound=ctypes.Structure)
#: A service's (publishers, subscribers, subscriber buffer) limits.
Limits = Tuple[int, int, int]

#: Nodes every service of a run allows.
MAX_NODES = 32
#: (publishers, subscribers, buffer) of the services between the world and one agent.
POINT_TO_POINT: Limits = (4, 4, 32)
#: (publishers, subscribers, buffer) of the services every process uses.
SHARED: Limits = (16, 16, 256)
#: Listeners and notifiers of a wake-up event service.
WAKE_LISTENERS, WAKE_NOTIFIERS = 2, 16

VOCABULARY = "learnpnp/world/vocabulary"
AGENT_REPORT = "learnpnp/agent-report"
HEARTBEAT = "learnpnp/heartbeat"
CONTROL = "learnpnp/control"


def snapshot_service(agent: int) -> str:
    """The service of agent ``agent``'s snapshots."""
    return f"learnpnp/world/agent/{agent}/snapshot"


def command_service(agent: int) -> str:
    """The service of agent ``agent``'s commands."""
    return f"learnpnp/world/agent/{agent}/command"


def wake_service(process: str) -> str:
    """The event service that wakes ``process`` (``world``, ``agent-0``, ...)."""
    return f"learnpnp/wake/{process}"


class WorldError(Exception):
    """The world cannot be served: a bad argument, environment or run."""


def namespace_config(prefix: str, root: str) -> iox.config.Config:
    """The iceoryx2 configuration of the run's namespace (prefix and root directory)."""
    config = iox.config.default()
    config.global_cfg.prefix = iox.FileName.new(prefix)
    config.global_cfg.root_path = iox.Path.new(root)
    return config


def pubsub_builder(
    node: iox.Node, name: str, payload: Type[ctypes.Structure], limits: Limits
) -> iox.ServiceBuilderPublishSubscribe:
    """The builder of publish-subscribe service ``name`` with the run's ``limits``."""
    publishers, subscribers, buffer = limits
    return (
        node.service_builder(iox.ServiceName.new(name))
        .publish_subscribe(payload)
        .max_publishers(publishers)
        .max_subscribers(subscribers)
        .max_nodes(MAX_NODES)
        .history_size(0)
        .subscriber_max_buffer_size(buffer)
        .enable_safe_overflow(True)
    )


def event_builder(node: iox.Node, name: str) -> iox.ServiceBuilderEvent:
    """The builder of wake-up event service ``name`` with the run's limits."""
    return (
        node.service_builder(iox.ServiceName.new(name))
        .event()
        .max_listeners(WAKE_LISTENERS)
        .max_notifiers(WAKE_NOTIFIERS)
        .max_nodes(MAX_NODES)
    )


def _opened(
    name: str, builder: Union[iox.ServiceBuilderPublishSubscribe, iox.ServiceBuilderEvent]
) -> Union[iox.PortFactoryPublishSubscribe, iox.PortFactoryEvent]:
    """The service ``builder`` opens, or a ``WorldError`` that names it."""
    try:
        return builder.open()
    except Exception as error:  # iceoryx2's open errors share no base class
        raise WorldError(
            f"cannot open the run's service {name!r} ({error!r}); a world process runs under "
            "learnpnp-supervisor --world-cmd, which creates the services first"
        ) from error


def copy_of(sample: iox.Sample, payload: Type[_Message]) -> _Message:
    """A copy of ``sample``'s payload (read once from shared memory, then released)."""
    value = payload()
    ctypes.memmove(ctypes.addressof(value), sample.payload_ptr, ctypes.sizeof(payload))
    return value


class WorldPorts:
    """Every port of the world process, on one node of the run's namespace."""

    def __init__(self, prefix: str, root: str, agents: int, notifies: bool) -> None:
        try:
            #: The world's node (None once closed).
            self.node: Optional[iox.Node] = (
                iox.NodeBuilder.new()
                .name(iox.NodeName.new("world"))
                .config(namespace_config(prefix, root))
                .signal_handling_mode(iox.SignalHandlingMode.Disabled)
                .create(iox.ServiceType.Ipc)
            )
        except Exception as error:
            raise WorldError(f"cannot create the iceoryx2 node in {root!r} ({error!r})") from error
        self._services: List[Union[iox.PortFactoryPublishSubscribe, iox.PortFactoryEvent]] = []
        self.vocabulary: iox.Publisher = self._publisher(VOCABULARY, WorldVocabulary, SHARED)
        self.heartbeat: iox.Publisher = self._publisher(HEARTBEAT, Heartbeat, SHARED)
        self.reports: iox.Subscriber = self._subscriber(AGENT_REPORT, AgentReport, SHARED)
        self.control: iox.Subscriber = self._subscriber(CONTROL, Control, SHARED)
        self.snapshots: List[iox.Publisher] = [
            self._publisher(snapshot_service(a), WorldSnapshot, POINT_TO_POINT) for a in range(agents)
        ]
        self.commands: List[iox.Subscriber] = [
            self._subscriber(command_service(a), WorldCommand, POINT_TO_POINT) for a in range(agents)
        ]
        #: The world's wake-up listener.
        self.wake: iox.Listener = self._event("world").listener_builder().create()
        #: Each agent's wake-up notifier (none when the run does not block).
        self.agent_wakes: List[iox.Notifier] = (
            [self._event(f"agent-{a}").notifier_builder().create() for a in range(agents)] if notifies else []
        )

    def _publisher(self, name: str, payload: Type[ctypes.Structure], limits: Limits) -> iox.Publisher:
        service = _opened(name, pubsub_builder(self.node, name, payload, limits))
        self._services.append(service)
        return service.publisher_builder().create()

    def _subscriber(self, name: str, payload: Type[ctypes.Structure], limits: Limits) -> iox.Subscriber:
        service = _opened(name, pubsub_builder(self.node, name, payload, limits))
        self._services.append(service)
        return service.subscriber_builder().create()

    def _event(self, process: str) -> iox.PortFactoryEvent:
        name = wake_service(process)
        service = _opened(name, event_builder(self.node, name))
        self._services.append(service)
        return service

    def send_snapshot(self, agent: int, snapshot: WorldSnapshot) -> None:
        """Publishes ``snapshot`` to ``agent``, then wakes it if the run blocks."""
        self.snapshots[agent].send_copy(snapshot)
        if self.agent_wakes:
            self.agent_wakes[agent].notify()

    def send_vocabulary(self, parts: Iterable[WorldVocabulary]) -> None:
        """Publishes every part of the vocabulary, then wakes every agent if the run blocks."""
        for part in parts:
            self.vocabulary.send_copy(part)
        for wake in self.agent_wakes:
            wake.notify()

    def close(self) -> None:
        """Releases the ports, the services and the node (the run's services live on)."""
        ports = [*self.agent_wakes, self.wake, *self.commands, *self.snapshots]
        ports += [self.control, self.reports, self.heartbeat, self.vocabulary]
        for port in ports:
            port.delete()
        self._services.clear()
        self.node = None


#: How long a hybrid wait yields its core before it blocks (as the Rust processes).
HYBRID_YIELD_NS = 200_000
#: The longest a blocked wait sleeps before the world looks again (heartbeat, control).
MAX_BLOCK_NS = 20_000_000
#: How much later than asked iceoryx2's timed wait may return (socket timeouts
#: count in scheduler ticks); a wait that must end on time blocks only until
#: this long before its end, and sleeps briefly in the last stretch.
TIMED_WAIT_SLACK_NS = 10_000_000
#: The short sleep of the last stretch before a deadline.
FINE_SLEEP_S = 0.0002

WAIT_STRATEGIES = ("spin", "yield", "block", "hybrid")


class Idle:
    """One wait of the world for a message, by the run's wait strategy.

    ``spin`` polls without pause; ``yield`` gives its core away between polls;
    ``block`` sleeps on the world's wake-up listener until an agent notifies
    it (or for at most ``MAX_BLOCK_NS``); ``hybrid`` yields for
    ``HYBRID_YIELD_NS``, then blocks.
    """

    def __init__(self, strategy: str, listener: iox.Listener) -> None:
        self.strategy = strategy
        self.listener = listener
        self.since = time.monotonic_ns()

    def pause(self, limit_ns: int = MAX_BLOCK_NS) -> None:
        """Pauses once between two polls, for at most about ``limit_ns``."""
        if self.strategy == "spin":
            return
        if self.strategy == "yield" or (
            self.strategy == "hybrid" and time.monotonic_ns() - self.since < HYBRID_YIELD_NS
        ):
            os.sched_yield()
            return
        limit_ns = min(limit_ns, MAX_BLOCK_NS)
        if limit_ns <= 0:
            os.sched_yield()
            return
        try:
            self.listener.timed_wait(iox.Duration.from_nanos(limit_ns))
        except iox.ListenerWaitError as error:
            if "Interrupt" not in repr(error):
                raise

    def pause_until(self, deadline_ns: int) -> None:
        """Pauses once, returning by ``deadline_ns`` (``time.monotonic_ns()``)."""
        left = deadline_ns - time.monotonic_ns()
        if self.strategy in ("block", "hybrid") and left <= TIMED_WAIT_SLACK_NS:
            time.sleep(min(max(left, 0) / 1e9, FINE_SLEEP_S))
            return
        self.pause(left - TIMED_WAIT_SLACK_NS)
