"""The runtime of the robot-side clients, imported directly (docs/services.md,
"Robot-side writers and readers"), against a real HTTP server on 127.0.0.1 that answers
as a store does; and what the generator ships of it. The live tests run the same
modules inside the generated packages against real services
(tests/live/test_clients_*.py, tests/live/test_service_end_to_end.py)."""

from __future__ import annotations

import ast
import json
import sys
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

import pytest

from spl.generators.clients import generator as clients, runtime as clients_runtime
from spl.generators.clients.runtime.reading import Listeners, PollingReader
from spl.generators.clients.runtime.transport import (
    StoreAccess,
    StoreClient,
    StoreError,
    StoreURLError,
    client_for,
)
from spl.generators.clients.runtime.writing import BatchingWriter, to_record

from support.service_models import product

RUNTIME = Path(clients_runtime.__file__).parent
ACCESS = StoreAccess("Shop", "SHOP_TOKEN", "SHOP_CA_FILE", "Sale", {"price": "double", "n": "int"})


class Store:
    """What the fake store was asked, and what it answers next (``refuse``: statuses
    to answer the next posts with, first to last)."""

    def __init__(self) -> None:
        self.posts: list[dict[str, Any]] = []
        self.headers: list[dict[str, str]] = []
        self.refuse: list[int] = []
        self.records = [{"id": i, "robot": "r", "timestamp": float(i)} for i in range(1, 6)]


@pytest.fixture
def store() -> Iterator[tuple[Store, str]]:
    state = Store()

    class Handler(BaseHTTPRequestHandler):
        def log_message(self, *args: object) -> None:
            pass

        def answer(self, status: int, body: Any) -> None:
            data = json.dumps(body).encode()
            self.send_response(status)
            self.send_header("Content-Type", "application/json")
            self.send_header("Content-Length", str(len(data)))
            self.end_headers()
            self.wfile.write(data)

        def do_POST(self) -> None:
            state.headers.append(dict(self.headers))
            body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
            if state.refuse:
                self.answer(state.refuse.pop(0), {"status": 0, "detail": "refused"})
                return
            state.posts.append(body)
            self.answer(201, {"ids": list(range(len(body["records"])))})

        def do_GET(self) -> None:
            state.headers.append(dict(self.headers))
            path, _, query = self.path.partition("?")
            fields = dict(pair.split("=") for pair in query.split("&"))
            after, limit = int(fields.get("after_id", 0)), int(fields["limit"])
            items = [r for r in state.records if r["id"] > after][:limit]
            more = items and items[-1]["id"] < state.records[-1]["id"]
            following = f"{path}?limit={limit}&after_id={items[-1]['id']}" if more else None
            self.answer(200, {"items": items, "next": following})

    server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield state, f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


def test_only_http_and_https_are_used_and_a_node_says_what_to_give_instead() -> None:
    with pytest.raises(StoreURLError, match="only http and https"):
        StoreClient(ACCESS, "file:///etc/passwd")
    with pytest.raises(SystemExit, match="URL of the Shop service"):
        client_for(lambda url: StoreClient(ACCESS, url), "ftp://store.example")
    client = client_for(lambda url: StoreClient(ACCESS, url, token="t"), "https://s.example/")
    assert client.base == "https://s.example/Shop" and client.context is not None


def test_the_token_comes_from_the_environment(monkeypatch, store) -> None:  # type: ignore[no-untyped-def]
    state, url = store
    monkeypatch.setenv("SHOP_TOKEN", "from-env")
    StoreClient(ACCESS, url).post([to_record(ACCESS.fields, "r", 1, {"price": 1, "n": 2})])
    assert state.headers[-1]["Authorization"] == "Bearer from-env"
    assert state.posts == [
        {"records": [{"robot": "r", "timestamp": 1.0, "data": {"price": 1.0, "n": 2}}]}
    ]


def test_a_read_follows_every_page_of_the_collection(store) -> None:  # type: ignore[no-untyped-def]
    _, url = store
    client = StoreClient(ACCESS, url, token="")
    assert [r["id"] for r in client.read(limit=2)] == [1, 2, 3, 4, 5]
    reader = PollingReader(client)
    assert len(reader.poll()) == 5 and reader.last_id == 5
    assert reader.poll() == []  # each record once


def test_errors_say_whether_sending_again_can_succeed(store) -> None:  # type: ignore[no-untyped-def]
    state, url = store
    state.refuse = [400, 503, 429]
    client = StoreClient(ACCESS, url, token="t")
    statuses = []
    for _ in range(3):
        with pytest.raises(StoreError) as error:
            client.post([])
        statuses.append((error.value.status, error.value.retryable))
    assert statuses == [(400, False), (503, True), (429, True)]
    with pytest.raises(StoreError) as unreachable:
        StoreClient(ACCESS, "http://127.0.0.1:1", timeout=5).post([])
    assert unreachable.value.status is None and unreachable.value.retryable


def test_a_record_takes_the_types_of_the_data_type_and_its_key() -> None:
    record = to_record(ACCESS.fields, "r1", 3, {"price": "2.5", "n": 4.0, "extra": 1}, "k-1")
    assert record == {"robot": "r1", "timestamp": 3.0, "data": {"price": 2.5, "n": 4}, "key": "k-1"}
    with pytest.raises(KeyError):
        to_record(ACCESS.fields, "r1", 3, {"price": 1.0})


def test_the_writer_retries_what_may_succeed_and_drops_what_cannot(store) -> None:  # type: ignore[no-untyped-def]
    state, url = store
    state.refuse = [503]  # the first batch is sent twice, then taken
    writer = BatchingWriter(StoreClient(ACCESS, url, token="t"), "r1", batch_size=2, linger=0.05)
    assert writer.submit(1.0, {"price": 1.0, "n": 1})
    assert not writer.submit(2.0, {"price": "not a number", "n": 1})  # not of the data type
    assert writer.flush(30)
    state.refuse = [400]
    assert writer.submit(3.0, {"price": 3.0, "n": 3})
    assert writer.flush(30)
    writer.close()
    assert [len(p["records"]) for p in state.posts] == [1]
    assert (writer.sent, writer.rejected) == (1, 2)
    keys = [r["key"] for p in state.posts for r in p["records"]]
    assert keys == [f"{writer.session}-0"]


def test_a_full_queue_drops_samples_rather_than_block(store) -> None:  # type: ignore[no-untyped-def]
    state, url = store
    state.refuse = [503] * 10_000  # the first batch is retried until the writer closes
    client = StoreClient(ACCESS, url, token="t")
    writer = BatchingWriter(client, "r1", batch_size=1, max_queue=1, linger=0.01)
    kept = [writer.submit(float(i), {"price": 1.0, "n": i}) for i in range(3)]
    writer.close(timeout=0.1)
    assert kept[0] and kept.count(False) == writer.dropped >= 1
    assert state.posts == [] and writer.sent == 0


def test_listeners_wait_for_their_subscribers_or_the_stop() -> None:
    connected, said = [0], []
    stop = threading.Event()
    listeners = Listeners(lambda: connected[0], 2, stop, said.append, recheck=30)
    waited: list[bool] = []
    thread = threading.Thread(target=lambda: waited.append(listeners.wait()))
    thread.start()
    connected[0] = 2
    while thread.is_alive():
        listeners.changed()  # as rospy reports a connection
        thread.join(0.05)
    assert waited == [True]
    connected[0] = 0
    stop.set()
    assert listeners.wait() is False
    assert Listeners(lambda: 0, -3, stop).wanted == 0


def test_every_client_package_ships_the_runtime_byte_for_byte() -> None:
    files = clients.generate(product())
    shipped = {p.name: p.read_bytes() for p in RUNTIME.glob("*.py")}
    packages = {path.split("/")[2] for path in files if path.startswith("clients/ros2/")}
    for package in packages:
        for root in (f"clients/ros1/{package}/src/{package}", f"clients/ros2/{package}/{package}"):
            runtime = {
                path.removeprefix(f"{root}/runtime/"): data
                for path, data in files.items()
                if path.startswith(f"{root}/runtime/")
            }
            assert runtime == shipped
    ros1 = files["clients/ros1/position_writer/setup.py"].decode()
    assert "packages=['position_writer', 'position_writer.runtime']" in ros1
    assert (
        'packages=[PACKAGE, PACKAGE + ".runtime"]'
        in files["clients/ros2/position_writer/setup.py"].decode()
    )


def test_the_runtime_needs_nothing_but_the_standard_library() -> None:
    """A robot installs no more than Python: the runtime's own modules are imported
    relatively, everything else is the standard library's."""
    for path in sorted(RUNTIME.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level:
                names = [node.module or ""]
            else:
                continue
            assert all(n.split(".")[0] in sys.stdlib_module_names for n in names), path.name
