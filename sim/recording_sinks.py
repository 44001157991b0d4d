"""Where a :class:`~baobab.sim.recording.Recorder`'s Foxglove messages go: a file or a live view.

A sink is attached to the recorder's ``foxglove.Context``; every channel logged on that context
reaches every attached sink. :class:`McapSink` writes an MCAP file, :class:`LiveSink` serves
Foxglove's WebSocket protocol with foxglove-sdk's server.
"""

from __future__ import annotations

import threading
from abc import ABC, abstractmethod
from pathlib import Path

import foxglove
from foxglove.websocket import Capability, ChannelView, Client, ServerListener

from baobab.sim.errors import BaobabError


class RecordingError(BaobabError):
    """A recording could not be written or served, or was fed out of time order."""


class Sink(ABC):
    """Where a :class:`Recorder`'s messages go. A sink is attached to one recorder only."""

    @abstractmethod
    def attach(self, context: foxglove.Context) -> None:
        """Start receiving the messages logged on ``context`` (called by the recorder)."""

    @abstractmethod
    def close(self) -> None:
        """Finish: flush and close the file, or stop the server (idempotent)."""

    def broadcast_time(self, time_ns: int) -> None:  # noqa: B027 (optional hook)
        """Tell live viewers the current time (ns); files ignore it."""


class McapSink(Sink):
    """Write an MCAP file (zstd-compressed chunks, with summary and message indexes).

    Args:
        path: the file to write; an existing file is replaced.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self._writer: foxglove.mcap.MCAPWriter | None = None

    def attach(self, context: foxglove.Context) -> None:
        if not self.path.parent.is_dir():
            raise RecordingError(f"{self.path}: cannot record, folder {self.path.parent} missing")
        try:
            self._writer = foxglove.open_mcap(self.path, allow_overwrite=True, context=context)
        except Exception as error:  # the SDK raises its own (Rust) error types
            raise RecordingError(f"{self.path}: cannot record: {error}") from error

    def close(self) -> None:
        if self._writer is not None:
            self._writer.close()
            self._writer = None


class LiveSink(Sink):
    """Serve the messages to Foxglove over its WebSocket protocol (foxglove-sdk's server).

    Foxglove connects to :attr:`url`. Clients see only what is logged after they subscribe,
    so republish static content (the world scene) periodically, e.g. at 1 Hz.

    Args:
        host: address to bind; the default serves this machine only.
        port: TCP port; 0 picks a free one (read it back from :attr:`port`).
        name: the server name shown in Foxglove.
    """

    def __init__(self, host: str = "127.0.0.1", port: int = 8765, name: str = "baobab") -> None:
        self.host = host
        self.name = name
        self._requested_port = port
        self._server: foxglove.WebSocketServer | None = None
        self._listener = _SubscriptionCounter()

    def attach(self, context: foxglove.Context) -> None:
        try:
            self._server = foxglove.start_server(
                name=self.name,
                host=self.host,
                port=self._requested_port,
                capabilities=[Capability.Time],
                server_listener=self._listener,
                context=context,
            )
        except Exception as error:  # the SDK raises its own (Rust) error types
            raise RecordingError(
                f"cannot serve Foxglove on {self.host}:{self._requested_port}: {error}"
            ) from error

    @staticmethod
    def check_address(host: str, port: int) -> None:
        """Raise unless a server could listen on ``host``:``port`` now (before a run starts).

        Resolves ``host`` as the server does (a name, an IPv4 or IPv6 address, ``[::1]``) and
        binds a probe socket to it, with the address reuse the server's listener sets too.

        Raises:
            RecordingError: the host does not resolve, is not this machine's, or the port is
                taken or not allowed.
        """
        import socket

        name = host[1:-1] if host.startswith("[") and host.endswith("]") else host
        try:
            if not name:
                raise OSError(0, "no address given")
            family, kind, protocol, _, address = socket.getaddrinfo(
                name, port, type=socket.SOCK_STREAM
            )[0]
            with socket.socket(family, kind, protocol) as probe:
                probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
                probe.bind(address)
        except (OSError, UnicodeError) as error:
            reason = getattr(error, "strerror", None) or str(error)
            raise RecordingError(f"cannot serve Foxglove on {host}:{port}: {reason}") from None

    @property
    def port(self) -> int:
        """The port the server listens on."""
        if self._server is None:
            raise RecordingError("the live server is not started (attach it to a Recorder)")
        return self._server.port

    @property
    def url(self) -> str:
        """The WebSocket URL to open in Foxglove."""
        return f"ws://{self.host}:{self.port}"

    def broadcast_time(self, time_ns: int) -> None:
        if self._server is not None:
            self._server.broadcast_time(time_ns)

    def wait_for_subscription(self, topic: str, timeout: float) -> bool:
        """Block until a client subscribes to ``topic`` or ``timeout`` (wall s) passes.

        For a run that should start only once Foxglove watches it, and for tests.
        """
        return self._listener.wait_for(topic, timeout)

    def close(self) -> None:
        if self._server is not None:
            self._server.stop()
            self._server = None


class _SubscriptionCounter(ServerListener):
    """Counts client subscriptions per topic; the server calls it from its own thread."""

    def __init__(self) -> None:
        self._changed = threading.Condition()
        self._counts: dict[str, int] = {}

    def wait_for(self, topic: str, timeout: float) -> bool:
        with self._changed:
            return self._changed.wait_for(lambda: self._counts.get(topic, 0) > 0, timeout)

    def on_subscribe(self, client: Client, channel: ChannelView) -> None:
        with self._changed:
            self._counts[channel.topic] = self._counts.get(channel.topic, 0) + 1
            self._changed.notify_all()

    def on_unsubscribe(self, client: Client, channel: ChannelView) -> None:
        with self._changed:
            self._counts[channel.topic] = max(0, self._counts.get(channel.topic, 0) - 1)
