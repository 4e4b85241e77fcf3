"""A subscribing reader's records as its store pushes them (docs/services.md,
"Robot-side writers and readers"): a client WebSocket of the standard library alone,
and the feed that falls back to polling while the subscription is down.
"""

from __future__ import annotations

import base64
import contextlib
import hashlib
import json
import logging
import os
import socket
import ssl
import threading
import urllib.parse
from collections.abc import Callable, Iterator
from typing import Any

from .reading import PollingReader
from .transport import StoreError

log = logging.getLogger(__name__)
WEBSOCKET_GUID = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11"  # RFC 6455, section 1.3


class WebSocketClosed(Exception):
    """The store's WebSocket ended (closed, refused, or silent too long)."""


class WebSocket:
    """A client WebSocket (RFC 6455) of the standard library alone: the opening
    handshake of a GET with ``Upgrade: websocket``, then text frames in, masked
    control frames out. Enough for a store's push subscription, nothing more."""

    def __init__(
        self,
        url: str,
        headers: dict[str, str],
        timeout: float,
        context: ssl.SSLContext | None,
    ) -> None:
        parts = urllib.parse.urlsplit(url)
        port = parts.port or (443 if parts.scheme == "https" else 80)
        host = parts.hostname or "localhost"
        sock = socket.create_connection((host, port), timeout=timeout)
        if context is not None:
            sock = context.wrap_socket(sock, server_hostname=host)
        self.sock = sock
        self.buffer = bytearray()  # received, not yet read from ``self.pos`` on
        self.pos = 0
        key = base64.b64encode(os.urandom(16)).decode()
        target = parts.path + (f"?{parts.query}" if parts.query else "")
        lines = [
            f"GET {target} HTTP/1.1",
            f"Host: {host}:{port}",
            "Upgrade: websocket",
            "Connection: Upgrade",
            f"Sec-WebSocket-Key: {key}",
            "Sec-WebSocket-Version: 13",
        ] + [f"{k}: {v}" for k, v in headers.items()]
        sock.sendall(("\r\n".join(lines) + "\r\n\r\n").encode())
        head = self._until(b"\r\n\r\n").decode("iso-8859-1").split("\r\n")
        status = head[0].split(" ", 2)
        if len(status) < 2 or status[1] != "101":
            raise WebSocketClosed(f"handshake refused: {head[0]}")
        fields = {k.strip().lower(): v.strip() for k, _, v in (h.partition(":") for h in head[1:])}
        # RFC 6455 fixes SHA-1 for the handshake's accept key: a checksum, not security
        accept = base64.b64encode(
            hashlib.sha1((key + WEBSOCKET_GUID).encode(), usedforsecurity=False).digest()
        )
        if fields.get("sec-websocket-accept") != accept.decode():
            raise WebSocketClosed("handshake answer does not match the key")

    def _until(self, mark: bytes) -> bytes:
        while (end := self.buffer.find(mark, self.pos)) < 0:
            self._fill()
        head = bytes(self.buffer[self.pos : end])
        self.pos = end + len(mark)
        return head

    def _fill(self) -> None:
        data = self.sock.recv(65536)
        if not data:
            raise WebSocketClosed("connection closed")
        del self.buffer[: self.pos]  # what was read goes once per receive, not per frame
        self.pos = 0
        self.buffer += data

    def _take(self, size: int) -> bytes:
        while len(self.buffer) - self.pos < size:
            self._fill()
        data = bytes(self.buffer[self.pos : self.pos + size])
        self.pos += size
        return data

    def _send(self, opcode: int, payload: bytes = b"") -> None:
        mask = os.urandom(4)
        length = len(payload)
        if length < 126:
            header = bytes([0x80 | opcode, 0x80 | length])
        elif length < 65536:
            header = bytes([0x80 | opcode, 0x80 | 126]) + length.to_bytes(2, "big")
        else:
            header = bytes([0x80 | opcode, 0x80 | 127]) + length.to_bytes(8, "big")
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        self.sock.sendall(header + mask + masked)

    def messages(self) -> Iterator[str]:
        """Each text message, as it arrives; a silent peer is pinged once per timeout
        and given up after two."""
        parts: list[bytes] = []
        quiet = 0
        while True:
            try:
                first, second = self._take(2)
            # socket.timeout is TimeoutError from Python 3.10 on, not on an older robot's
            except (socket.timeout, TimeoutError):  # noqa: UP041
                quiet += 1
                if quiet > 1:
                    raise WebSocketClosed("no answer to a ping") from None
                self._send(0x9)
                continue
            quiet = 0
            final, opcode = first & 0x80, first & 0x0F
            length = second & 0x7F
            if length == 126:
                length = int.from_bytes(self._take(2), "big")
            elif length == 127:
                length = int.from_bytes(self._take(8), "big")
            mask = self._take(4) if second & 0x80 else b""
            payload = self._take(length)
            if mask:
                payload = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
            if opcode == 0x8:
                with contextlib.suppress(OSError):
                    self._send(0x8, payload[:2])
                raise WebSocketClosed("closed by the store")
            if opcode == 0x9:
                self._send(0xA, payload)
                continue
            if opcode in (0x0, 0x1, 0x2):
                parts.append(payload)
                if final:
                    yield b"".join(parts).decode("utf-8")
                    parts = []

    def close(self) -> None:
        with contextlib.suppress(OSError):
            self._send(0x8, (1000).to_bytes(2, "big"))
        self.sock.close()


class Feed:
    """A reader's records as the store pushes them: a WebSocket subscription on the
    collection from the last id published (the store sends what came since, then each
    new record), and while it is down a poll every ``period``, then a new subscription.
    Each record is handed to ``publish`` once, in id order."""

    def __init__(
        self,
        reader: PollingReader,
        publish: Callable[[dict[str, Any]], Any],
        period: float,
        stop: threading.Event,
    ) -> None:
        self.reader, self.publish, self.period, self.stop = reader, publish, period, stop

    def _wanted(self, record: dict[str, Any]) -> bool:
        reader = self.reader
        if reader.robot is not None and record.get("robot") != reader.robot:
            return False
        return reader.start is None or record.get("timestamp", 0.0) >= reader.start

    def run(self) -> None:
        client = self.reader.client
        while not self.stop.is_set():
            query = urllib.parse.urlencode({"after_id": self.reader.last_id})
            headers = {"Accept": "application/json"}
            if client.token:
                headers["Authorization"] = f"Bearer {client.token}"
            socket_ = None
            try:
                socket_ = WebSocket(
                    f"{client.base}/{client.access.collection}?{query}",
                    headers,
                    max(5.0, 3 * self.period),
                    client.context,
                )
                for text in socket_.messages():
                    record = json.loads(text)
                    if record["id"] > self.reader.last_id:
                        self.reader.last_id = record["id"]
                        if self._wanted(record):
                            self.publish(record)
                    if self.stop.is_set():
                        return
            except (WebSocketClosed, OSError, ValueError, KeyError) as error:
                log.warning(
                    "store subscription down (%s): polling every %.1f s", error, self.period
                )
            finally:
                if socket_ is not None:
                    socket_.close()
            try:
                for record in self.reader.poll():
                    self.publish(record)
            except StoreError as error:
                log.warning("store not readable: %s", error)
            self.stop.wait(self.period)
