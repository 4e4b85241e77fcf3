"""The clients' runtime WebSocket (RFC 6455, the standard library alone), imported
directly, against a real socket on 127.0.0.1 that answers as a store's push
subscription does: the opening handshake and its accept key, text messages whole or in
fragments, pings answered, the close; and what a Feed hands on. The live test
tests/live/test_clients_feed.py runs the feed against a real service."""

from __future__ import annotations

import base64
import hashlib
import json
import socket
import threading
from collections.abc import Callable, Iterator

import pytest

from spl.generators.clients.runtime.feed import WEBSOCKET_GUID, Feed, WebSocket, WebSocketClosed
from spl.generators.clients.runtime.reading import PollingReader
from spl.generators.clients.runtime.transport import StoreAccess, StoreClient

ACCESS = StoreAccess("Shop", "SHOP_TOKEN", "SHOP_CA_FILE", "Sale", {"price": "double"})


def frame(opcode: int, payload: bytes, final: bool = True) -> bytes:
    """A frame as a server sends it: unmasked."""
    head = bytes([(0x80 if final else 0) | opcode])
    if len(payload) < 126:
        return head + bytes([len(payload)]) + payload
    return head + bytes([126]) + len(payload).to_bytes(2, "big") + payload


def read_frame(conn: socket.socket) -> tuple[int, bytes]:
    """A frame as a client sends it: masked."""
    first, second = conn.recv(2, socket.MSG_WAITALL)
    length = second & 0x7F
    mask = conn.recv(4, socket.MSG_WAITALL)
    data = conn.recv(length, socket.MSG_WAITALL) if length else b""
    return first & 0x0F, bytes(b ^ mask[i % 4] for i, b in enumerate(data))


Serve = Callable[[socket.socket, dict[str, str]], None]


@pytest.fixture
def server() -> Iterator[Callable[[Serve], tuple[str, threading.Thread]]]:
    """``start(serve)``: a URL whose one connection ``serve`` answers after the head, and
    the thread that serves it (joined before what it saw is read)."""
    listener = socket.create_server(("127.0.0.1", 0))
    threads = []
    seen: list[dict[str, str]] = []

    def start(serve: Serve) -> tuple[str, threading.Thread]:
        def run() -> None:
            conn, _ = listener.accept()
            with conn:
                head = b""
                while b"\r\n\r\n" not in head:
                    head += conn.recv(1024)
                lines = head.decode().split("\r\n")
                fields = {k.lower(): v.strip() for k, _, v in (x.partition(":") for x in lines)}
                fields["request"] = lines[0]
                seen.append(fields)
                serve(conn, fields)

        thread = threading.Thread(target=run, daemon=True)
        thread.start()
        threads.append(thread)
        return f"http://127.0.0.1:{listener.getsockname()[1]}/Shop/Sale?after_id=3", thread

    yield start
    listener.close()
    for thread in threads:
        thread.join(10)


def accept(conn: socket.socket, fields: dict[str, str], key: str | None = None) -> None:
    digest = hashlib.sha1((fields["sec-websocket-key"] + WEBSOCKET_GUID).encode()).digest()
    answer = key or base64.b64encode(digest).decode()
    conn.sendall(
        "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        f"Sec-WebSocket-Accept: {answer}\r\n\r\n".encode()
    )


def test_messages_arrive_whole_pings_are_answered_and_the_close_ends_them(server) -> None:  # type: ignore[no-untyped-def]
    pongs: list[tuple[int, bytes]] = []

    def serve(conn: socket.socket, fields: dict[str, str]) -> None:
        accept(conn, fields)
        conn.sendall(frame(0x1, b'{"id": 4}') + frame(0x9, b"ping?"))
        pongs.append(read_frame(conn))
        long = json.dumps({"id": 5, "text": "x" * 300}).encode()
        conn.sendall(frame(0x1, long[:100], final=False) + frame(0x0, long[100:]))
        conn.sendall(frame(0x8, (1000).to_bytes(2, "big")))
        pongs.append(read_frame(conn))  # the close, answered

    url, serving = server(serve)
    socket_ = WebSocket(url, {"Authorization": "Bearer t"}, timeout=10, context=None)
    received = []
    with pytest.raises(WebSocketClosed, match="closed by the store"):
        for text in socket_.messages():
            received.append(json.loads(text)["id"])
    serving.join(10)
    socket_.close()
    assert received == [4, 5]
    assert pongs == [(0xA, b"ping?"), (0x8, (1000).to_bytes(2, "big"))]


def test_a_refused_or_forged_handshake_is_no_websocket(server) -> None:  # type: ignore[no-untyped-def]
    url, _ = server(lambda conn, _: conn.sendall(b"HTTP/1.1 401 Unauthorized\r\n\r\n"))
    with pytest.raises(WebSocketClosed, match=r"handshake refused: HTTP/1\.1 401"):
        WebSocket(url, {}, timeout=10, context=None)
    url, _ = server(lambda conn, fields: accept(conn, fields, key="forged"))
    with pytest.raises(WebSocketClosed, match="does not match the key"):
        WebSocket(url, {}, timeout=10, context=None)


def test_a_silent_store_is_pinged_once_then_given_up(server) -> None:  # type: ignore[no-untyped-def]
    pings: list[tuple[int, bytes]] = []

    def serve(conn: socket.socket, fields: dict[str, str]) -> None:
        accept(conn, fields)
        pings.append(read_frame(conn))
        conn.recv(1024)  # until the client closes

    url, serving = server(serve)
    socket_ = WebSocket(url, {}, timeout=0.5, context=None)
    with pytest.raises(WebSocketClosed, match="no answer to a ping"):
        next(socket_.messages())
    socket_.close()
    serving.join(10)
    assert pings == [(0x9, b"")]


def test_a_feed_subscribes_after_its_last_record_and_hands_on_the_wanted_ones(server) -> None:  # type: ignore[no-untyped-def]
    stop = threading.Event()
    requests: list[str] = []

    def serve(conn: socket.socket, fields: dict[str, str]) -> None:
        requests.append(fields["request"])
        accept(conn, fields)
        records = [
            {"id": 3, "robot": "mine", "timestamp": 1.0},
            {"id": 4, "robot": "other", "timestamp": 1.0},
            {"id": 5, "robot": "mine", "timestamp": 0.5},
            {"id": 6, "robot": "mine", "timestamp": 1.0},
        ]
        conn.sendall(b"".join(frame(0x1, json.dumps(r).encode()) for r in records))
        conn.recv(1024)

    url, serving = server(serve)
    base = url.split("/Shop/")[0]
    reader = PollingReader(StoreClient(ACCESS, base, token="t"), robot="mine", start=1.0)
    reader.last_id = 3
    published: list[int] = []

    def publish(record: dict[str, object]) -> None:
        published.append(int(str(record["id"])))
        stop.set()  # the feed returns after the message it was handed

    Feed(reader, publish, 0.1, stop).run()
    serving.join(10)
    assert requests == ["GET /Shop/Sale?after_id=3 HTTP/1.1"]
    assert published == [6]  # 3 was published before, 4 is another robot's, 5 too early
    assert reader.last_id == 6
