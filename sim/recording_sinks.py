"""Where a :class:`~baobab.sim.recording.Recorder`'s Foxglove messages go: a file or a live view.

A sink is attached to the recorder's ``foxglove.Context``; every channel logged on that context
reaches every attached sink. :class:`McapSink` writes an MCAP file, :class:`LiveSink` serves
Foxglove's WebSocket protocol with foxglove-sdk's server, behind a relay that also accepts the
protocol's older name (:mod:`baobab.sim.live_relay`).
"""

from __future__ import annotations

import sys
import threading
from abc import ABC, abstractmethod
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import foxglove
from foxglove.websocket import Capability, ChannelView, Client, ServerListener

from baobab.sim.errors import BaobabError
from baobab.sim.output_file import OutputFile

if TYPE_CHECKING:
    from baobab.sim.live_relay import SubprotocolRelay


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

    def new_subscriptions(self) -> set[str]:
        """Topics a live viewer subscribed to since the last call (to resend latched ones).

        Files have no viewers: none by default.
        """
        return set()


class McapSink(Sink):
    """Write an MCAP file (zstd-compressed chunks, with summary and message indexes).

    The file is written under a temporary name and moved into place by :meth:`close`. If
    writing fails meanwhile (disk full), recording stops: ``on_failure`` is told once, the
    partial file is removed, and the run goes on (see :class:`~baobab.sim.output_file.OutputFile`).

    Args:
        path: the file to write; an existing file is replaced.
        on_failure: told why recording stopped (default: :meth:`close` raises RecordingError).
    """

    def __init__(self, path: str | Path, on_failure: Callable[[str], None] | None = None) -> None:
        self.path = Path(path)
        self.on_failure = on_failure
        self._file: OutputFile | None = None
        self._writer: foxglove.mcap.MCAPWriter | None = None

    def attach(self, context: foxglove.Context) -> None:
        if not self.path.parent.is_dir():
            raise RecordingError(f"{self.path}: cannot record, folder {self.path.parent} missing")
        try:
            self._file = OutputFile(self.path, self._failed)
            self._writer = foxglove.open_mcap(self._file, context=context)
        except Exception as error:  # the SDK raises its own (Rust) error types
            if self._file is not None:
                self._file.discard()
            raise RecordingError(f"{self.path}: cannot record: {error}") from error

    @property
    def failure(self) -> str | None:
        """Why recording stopped before the end, or None."""
        return None if self._file is None else self._file.failure

    def _failed(self, reason: str) -> None:
        if self.on_failure is not None:
            self.on_failure(reason)

    def close(self) -> None:
        if self._writer is not None:
            self._writer.close()
            self._writer = None
        file = self._file
        if file is not None and not file.closed:
            file.close()
            if file.failure is not None and self.on_failure is None:
                raise RecordingError(f"{self.path}: recording stopped: {file.failure}")


class LiveSink(Sink):
    """Serve the messages to Foxglove over its WebSocket protocol.

    Foxglove connects to :attr:`url` with either subprotocol, ``foxglove.sdk.v1`` or the older
    ``foxglove.websocket.v1``. Clients see only what is logged after they subscribe, so
    republish static content (the world scene) periodically, e.g. at 1 Hz, or latch it
    (:meth:`Recorder.log_static_transforms`).

    Args:
        host: address to bind; the default serves this machine only.
        port: TCP port; 0 picks a free one (read it back from :attr:`port`).
        name: the server name shown in Foxglove.
        report: told, once per client address, that a handshake was refused (from the
            server's thread); the default prints to stderr.
    """

    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 8765,
        name: str = "baobab",
        *,
        report: Callable[[str], None] | None = None,
    ) -> None:
        self.host = host
        self.name = name
        self._requested_port = port
        self._report = report or _to_stderr
        self._server: foxglove.WebSocketServer | None = None
        self._relay: SubprotocolRelay | None = None
        self._listener = _SubscriptionCounter()

    def attach(self, context: foxglove.Context) -> None:
        from baobab.sim.live_relay import SubprotocolRelay, listening_socket

        where = f"{self.host}:{self._requested_port}"
        try:
            # The public port first: a port in use fails before anything starts.
            sock = listening_socket(self.host, self._requested_port)
        except OSError as error:
            raise RecordingError(f"cannot serve Foxglove on {where}: {error}") from error
        try:
            self._server = foxglove.start_server(
                name=self.name,
                host="127.0.0.1",  # reached only through the relay
                port=0,
                capabilities=[Capability.Time],
                server_listener=self._listener,
                context=context,
            )
            upstream = f"ws://127.0.0.1:{self._server.port}"
            self._relay = SubprotocolRelay(sock, upstream, self._report)
        except Exception as error:  # the SDK raises its own (Rust) error types
            sock.close()
            self.close()
            raise RecordingError(f"cannot serve Foxglove on {where}: {error}") from error

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
        if self._relay is None:
            raise RecordingError("the live server is not started (attach it to a Recorder)")
        return self._relay.port

    @property
    def url(self) -> str:
        """The WebSocket URL to open in Foxglove."""
        return f"ws://{self.host}:{self.port}"

    def broadcast_time(self, time_ns: int) -> None:
        if self._server is not None:
            self._server.broadcast_time(time_ns)

    def new_subscriptions(self) -> set[str]:
        return self._listener.take_new()

    def wait_for_subscription(self, topic: str, timeout: float) -> bool:
        """Block until a client subscribes to ``topic`` or ``timeout`` (wall s) passes.

        For a run that should start only once Foxglove watches it, and for tests.
        """
        return self._listener.wait_for(topic, timeout)

    def close(self) -> None:
        if self._relay is not None:
            self._relay.close()
            self._relay = None
        if self._server is not None:
            self._server.stop()
            self._server = None


class _SubscriptionCounter(ServerListener):
    """Counts client subscriptions per topic; the server calls it from its own thread."""

    def __init__(self) -> None:
        self._changed = threading.Condition()
        self._counts: dict[str, int] = {}
        self._new: set[str] = set()

    def take_new(self) -> set[str]:
        """Topics subscribed to since the last call."""
        with self._changed:
            new, self._new = self._new, set()
            return new

    def wait_for(self, topic: str, timeout: float) -> bool:
        with self._changed:
            return self._changed.wait_for(lambda: self._counts.get(topic, 0) > 0, timeout)

    def on_subscribe(self, client: Client, channel: ChannelView) -> None:
        with self._changed:
            self._counts[channel.topic] = self._counts.get(channel.topic, 0) + 1
            self._new.add(channel.topic)
            self._changed.notify_all()

    def on_unsubscribe(self, client: Client, channel: ChannelView) -> None:
        with self._changed:
            self._counts[channel.topic] = max(0, self._counts.get(channel.topic, 0) - 1)


def _to_stderr(message: str) -> None:
    print(message, file=sys.stderr)
