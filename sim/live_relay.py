"""Serve Foxglove's WebSocket protocol under both of its names, in front of foxglove-sdk's server.

Foxglove's live protocol (the spec in ``foxglove/ws-protocol``, ``docs/spec.md``) was negotiated
as the WebSocket subprotocol ``foxglove.websocket.v1`` until 2025 and as ``foxglove.sdk.v1``
since: the same messages under a new name. foxglove-sdk's server accepts only the new name and
answers HTTP 400 to every client that asks for the old one (the reference
``@foxglove/ws-protocol`` client, older Lichtblick releases, PlotJuggler, roslibjs-foxglove);
it has no setting to accept both.

So the public port belongs to a :class:`SubprotocolRelay` built on ``websockets``: it completes
the handshake for either name and relays each client's frames, unchanged, over its own
connection to the SDK's server on a loopback port. The SDK keeps doing the protocol (channel
advertisements, subscriptions, per-client queues that drop the oldest data when a client is
slow); the relay only forwards and stops reading when a client stops reading, so the SDK's
queue, not the relay, absorbs a slow client.

A refused handshake (wrong subprotocol, a plain HTTP request) is reported once per client
address: a viewer retrying every second would otherwise fill the terminal.
"""

from __future__ import annotations

import asyncio
import contextlib
import socket
import threading
from collections.abc import Callable, Coroutine
from http import HTTPStatus
from typing import Any, TypeVar

from websockets.asyncio.client import ClientConnection, connect
from websockets.asyncio.server import Server, ServerConnection, serve
from websockets.exceptions import ConnectionClosed, InvalidHandshake
from websockets.frames import CloseCode
from websockets.http11 import Request, Response
from websockets.typing import Subprotocol

SDK_SUBPROTOCOL = "foxglove.sdk.v1"
LEGACY_SUBPROTOCOL = "foxglove.websocket.v1"
SUBPROTOCOLS = (SDK_SUBPROTOCOL, LEGACY_SUBPROTOCOL)
"""Served subprotocols, preferred first (a client offering both gets ``foxglove.sdk.v1``)."""
REASON_LIMIT = 200
"""Characters of a refusal's reason shown (it may echo what the client sent)."""

T = TypeVar("T")


def listening_socket(host: str, port: int) -> socket.socket:
    """A TCP socket listening on ``host``:``port`` (0: a free port), one address like the SDK's.

    Raises:
        OSError: the host does not resolve or the port is taken.
    """
    family = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0][0]
    return socket.create_server((host, port), family=family)


class SubprotocolRelay:
    """Accept Foxglove clients of either subprotocol on ``sock``; relay each to ``upstream``.

    Runs an asyncio loop in a daemon thread; :meth:`close` stops it.

    Args:
        sock: the public listening socket (the relay owns it from now on).
        upstream: WebSocket URL of foxglove-sdk's server (on loopback).
        report: told once per client address why a handshake was refused; called from the
            relay's thread.
    """

    def __init__(self, sock: socket.socket, upstream: str, report: Callable[[str], None]) -> None:
        self.port: int = sock.getsockname()[1]
        self._upstream = upstream
        self._report = report
        self._reported: set[str] = set()
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(
            target=self._loop.run_forever, name="foxglove relay", daemon=True
        )
        self._thread.start()
        self._server: Server | None = None
        try:
            self._server = self._call(self._serve(sock))
        except BaseException:
            sock.close()
            self.close()
            raise

    def close(self) -> None:
        """Close every client connection and the port, then stop the thread (idempotent)."""
        if self._loop.is_closed():
            return
        server, self._server = self._server, None
        if server is not None:
            self._call(_shut(server))
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join()
        self._loop.close()

    def _call(self, coroutine: Coroutine[Any, Any, T]) -> T:
        """Run ``coroutine`` on the relay's loop and wait for its result."""
        return asyncio.run_coroutine_threadsafe(coroutine, self._loop).result()

    async def _serve(self, sock: socket.socket) -> Server:
        return await serve(
            self._relay,
            sock=sock,
            subprotocols=[Subprotocol(name) for name in SUBPROTOCOLS],
            process_response=self._note_refusal,
            compression=None,  # the SDK does not compress either; spare the CPU
        )

    async def _relay(self, client: ServerConnection) -> None:
        """Pass frames both ways until either side closes."""
        try:
            upstream = await connect(
                self._upstream,
                subprotocols=[Subprotocol(SDK_SUBPROTOCOL)],
                compression=None,
                max_size=None,  # costmaps and scenes may exceed websockets' 1 MiB default
                ping_interval=None,  # loopback
            )
        except (OSError, InvalidHandshake, TimeoutError) as error:
            host = _host(client)
            self._report_once(host, f"cannot relay {host} to foxglove-sdk's server: {error}")
            await client.close(CloseCode.INTERNAL_ERROR, "the live server is not available")
            return
        async with upstream:
            await _until_first_ends(_pump(client, upstream), _pump(upstream, client))

    def _note_refusal(
        self, connection: ServerConnection, request: Request, response: Response
    ) -> None:
        """Report a refused handshake (before the refusal is sent)."""
        if response.status_code == HTTPStatus.SWITCHING_PROTOCOLS:
            return
        error = connection.protocol.handshake_exc
        reason = str(error) if error is not None else response.reason_phrase
        if len(reason) > REASON_LIMIT:
            reason = reason[:REASON_LIMIT] + "..."
        host, status = _host(connection), response.status_code
        self._report_once(host, f"refused a client at {host} (HTTP {status}: {reason})")

    def _report_once(self, host: str, what: str) -> None:
        if host not in self._reported:
            self._reported.add(host)
            self._report(f"live: {what}; further failures from {host} are not shown")


async def _pump(
    source: ServerConnection | ClientConnection, sink: ServerConnection | ClientConnection
) -> None:
    """Forward every frame from ``source`` to ``sink`` (text stays text, binary binary)."""
    with contextlib.suppress(ConnectionClosed):
        async for message in source:
            await sink.send(message)


async def _until_first_ends(*coroutines: Coroutine[Any, Any, None]) -> None:
    """Run the coroutines until one returns, then cancel the others."""
    tasks = [asyncio.create_task(coroutine) for coroutine in coroutines]
    try:
        await asyncio.wait(tasks, return_when=asyncio.FIRST_COMPLETED)
    finally:
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)


async def _shut(server: Server) -> None:
    server.close()  # closes every client connection (1001, going away)
    await server.wait_closed()


def _host(connection: ServerConnection) -> str:
    """The client's IP address (a retry comes from a new port, so the port is left out)."""
    return str(connection.remote_address[0])
