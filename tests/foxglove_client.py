"""A Foxglove WebSocket client written from the protocol's public spec, for testing ``--live``.

The spec is ``docs/spec.md`` of github.com/foxglove/ws-protocol ("Foxglove WebSocket protocol
v1"): JSON text messages with an ``op`` field (``serverInfo`` first, then ``advertise``,
``unadvertise``, ``status``), binary messages with a one-byte opcode (1 message data: uint32
subscription id, uint64 receive time ns, payload; 2 time: uint64 ns), little-endian; the client
sends ``subscribe`` with ids of its own choosing. Protobuf channels carry a base64
``FileDescriptorSet`` as schema. Nothing here uses baobab or foxglove-sdk, so the server is
checked against the spec, not against itself.
"""

from __future__ import annotations

import base64
import json
import struct
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

from google.protobuf import descriptor_pb2, descriptor_pool, message_factory
from websockets.sync.client import ClientConnection, connect
from websockets.typing import Subprotocol

MESSAGE_DATA = 1
TIME = 2


@dataclass
class Received:
    """One message data frame, decoded with its channel's advertised schema."""

    topic: str
    log_time: int
    message: Any


@contextmanager
def spec_client(
    url: str, subprotocol: str, *, timeout: float, source: str | None = None
) -> Iterator[SpecClient]:
    """A client connected asking for ``subprotocol`` only (from address ``source`` if given),
    past the ``serverInfo`` message; closed on exit."""
    extra = {} if source is None else {"source_address": (source, 0)}
    with connect(
        url,
        subprotocols=[Subprotocol(subprotocol)],
        max_size=None,
        open_timeout=timeout,
        compression=None,
        **extra,
    ) as connection:
        client = SpecClient(connection, timeout)
        client.server_info = json.loads(connection.recv(timeout=timeout))
        assert client.server_info["op"] == "serverInfo", "the spec: serverInfo comes first"
        yield client


@dataclass
class SpecClient:
    """A connected client (made by :func:`spec_client`).

    Attributes:
        connection: the WebSocket connection.
        server_info: the ``serverInfo`` message.
        channels: advertised channels by id.
        times: the server times received (ns).
    """

    connection: ClientConnection
    timeout: float
    server_info: dict[str, Any] = field(default_factory=dict)
    channels: dict[int, dict[str, Any]] = field(default_factory=dict)
    times: list[int] = field(default_factory=list)
    _subscriptions: dict[int, dict[str, Any]] = field(default_factory=dict)
    _decoders: dict[int, Callable[[bytes], Any]] = field(default_factory=dict)

    def topics(self) -> set[str]:
        return {channel["topic"] for channel in self.channels.values()}

    def wait_for_topics(self, topics: set[str]) -> None:
        """Read until every topic in ``topics`` is advertised."""
        while not topics <= self.topics():
            self._read()

    def subscribe(self, topics: set[str]) -> None:
        """Subscribe to the channels of ``topics``, with subscription ids 100, 101, ..."""
        chosen = [c for c in self.channels.values() if c["topic"] in topics]
        first = 100 + len(self._subscriptions)
        subscriptions = [{"id": first + i, "channelId": c["id"]} for i, c in enumerate(chosen)]
        for subscription, channel in zip(subscriptions, chosen, strict=True):
            self._subscriptions[subscription["id"]] = channel
        self.connection.send(json.dumps({"op": "subscribe", "subscriptions": subscriptions}))

    def receive_until(self, done: Callable[[list[Received]], bool]) -> list[Received]:
        """Every message data frame read until ``done(received so far)`` holds."""
        received: list[Received] = []
        while not done(received):
            item = self._read()
            if item is not None:
                received.append(item)
        return received

    def _read(self) -> Received | None:
        frame = self.connection.recv(timeout=self.timeout)
        if isinstance(frame, str):
            message = json.loads(frame)
            if message["op"] == "advertise":
                self.channels.update({c["id"]: c for c in message["channels"]})
            elif message["op"] == "unadvertise":
                for channel_id in message["channelIds"]:
                    self.channels.pop(channel_id, None)
            return None
        opcode = frame[0]
        if opcode == TIME:
            (time_ns,) = struct.unpack_from("<Q", frame, 1)
            self.times.append(time_ns)
            return None
        assert opcode == MESSAGE_DATA, f"unexpected binary opcode {opcode}"
        subscription_id, log_time = struct.unpack_from("<IQ", frame, 1)
        channel = self._subscriptions[subscription_id]
        payload = bytes(frame[13:])
        return Received(channel["topic"], log_time, self._decoder(channel)(payload))

    def _decoder(self, channel: dict[str, Any]) -> Callable[[bytes], Any]:
        decoder = self._decoders.get(channel["id"])
        if decoder is None:
            if channel["encoding"] == "json":
                decoder = json.loads
            else:
                assert channel["encoding"] == "protobuf", channel["encoding"]
                decoder = protobuf_decoder(channel["schemaName"], channel["schema"])
            self._decoders[channel["id"]] = decoder
        return decoder


def protobuf_decoder(name: str, schema: str) -> Callable[[bytes], Any]:
    """A parser for message type ``name`` from a base64 ``FileDescriptorSet``."""
    files = descriptor_pb2.FileDescriptorSet.FromString(base64.b64decode(schema))
    pool = descriptor_pool.DescriptorPool()
    for file in files.file:  # dependencies come first
        pool.Add(file)
    message_class = message_factory.GetMessageClass(pool.FindMessageTypeByName(name))
    return message_class.FromString
