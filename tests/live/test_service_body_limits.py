"""The size limit on request bodies of the generated services (docs/services.md, "Limits"),
through uvicorn as deployed: a body announced larger than ``MAX_BODY`` (default
``MAX_BATCH`` x 16 KiB) is answered 413 with the reason before any of it is sent, a
chunked body without a length is answered 413 as soon as it passes the limit, without
the server waiting for its end, and the connection is closed either way; this holds for
the write endpoints (the only ones that take a body) and for every other one. A body
within the limit is stored as before. A WebSocket subscriber's message over 64 KiB
(the service reads them only to drop them) closes its connection with 1009."""

from __future__ import annotations

import http.client
import json
from pathlib import Path

import pytest
import websockets

from spl.generators.service import generator as service

from support.oversized_bodies import announced, chunked
from support.service_models import product
from support.service_runtime import TOKEN, RunningService, request, write_files
from support.subscription_clients import Frames, websocket_url

PACKAGE = "position_store_service"
STORE = "/PositionStore"
LIMIT = 4096
WRITE = {
    "Authorization": f"Bearer {TOKEN}",
    "Content-Type": "application/json",
    "Accept": "application/json",
}
WRITES = [f"{STORE}/records", f"{STORE}/records/batch"]


@pytest.fixture(scope="module")
def directory(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = write_files(service.generate(product()), tmp_path_factory.mktemp("limits"))
    return root / "services" / "PositionStore"


@pytest.fixture(scope="module")
def limited(directory: Path):  # type: ignore[no-untyped-def]
    environment = {"POSITION_STORE_TOKEN": TOKEN, "TRANSFORMER": "off", "MAX_BODY": str(LIMIT)}
    running = RunningService(directory, PACKAGE, environment).start()
    yield running
    running.stop()


def one(i: int) -> dict:
    return {"robot": "limits", "timestamp": 1.0 + i, "data": {"lat": 1.0, "lon": 2.0}}


@pytest.mark.parametrize("path", WRITES)
def test_a_body_announced_over_the_limit_is_refused_before_it_is_sent(limited, path) -> None:
    refused = announced(limited.port, path, 20_000_000, WRITE)
    assert refused.status == 413
    assert refused.body == {
        "status": 413,
        "detail": f"the body has 20000000 bytes; at most {LIMIT} are taken",
    }
    assert refused.headers["connection"] == "close" and refused.closed


@pytest.mark.parametrize("path", WRITES)
def test_a_chunked_body_is_refused_once_it_passes_the_limit(limited, path) -> None:
    refused = chunked(limited.port, path, LIMIT + 1, WRITE, chunk=1000)
    assert refused.status == 413
    assert refused.body == {"status": 413, "detail": f"the body has more than {LIMIT} bytes"}
    assert refused.headers["connection"] == "close" and refused.closed


def test_bodies_within_the_limit_are_stored_and_the_size_comes_before_the_token(limited) -> None:
    base = limited.url + STORE
    batch = {"records": [one(i) for i in range(10)]}
    assert len(json.dumps(batch)) < LIMIT
    status, _, answer = request("POST", f"{base}/records/batch", batch)
    assert status == 201 and len(answer["ids"]) == 10
    records = [one(i) for i in range(60)]
    assert len(json.dumps({"records": records})) > LIMIT
    status, _, answer = request("POST", f"{base}/records/batch", {"records": records})
    assert status == 413 and answer["detail"].endswith(f"at most {LIMIT} are taken")
    # no token: too large is known before who sends it matters
    status, _, answer = request("POST", f"{base}/records/batch", {"records": records}, token=None)
    assert status == 413
    # a whole chunked body within the limit is read and stored
    body = json.dumps(batch).encode()
    connection = http.client.HTTPConnection("127.0.0.1", limited.port, timeout=30)
    try:
        connection.request(
            "POST", f"{STORE}/records/batch", iter([body[:1000], body[1000:]]),
            {**WRITE, "Transfer-Encoding": "chunked"}, encode_chunked=True,
        )  # fmt: skip
        answer = connection.getresponse()
        assert answer.status == 201 and len(json.loads(answer.read())["ids"]) == 10
    finally:
        connection.close()


@pytest.mark.parametrize(
    ("method", "path"),
    [
        ("GET", f"{STORE}/records"),
        ("GET", "/"),
        ("DELETE", f"{STORE}/subscriptions/00000000-0000-0000-0000-000000000000"),
        ("OPTIONS", f"{STORE}/records"),
    ],
)
def test_every_other_endpoint_has_the_same_limit(limited, method: str, path: str) -> None:
    refused = announced(limited.port, path, LIMIT + 1, WRITE, method=method)
    assert refused.status == 413 and refused.closed
    assert refused.body["detail"] == f"the body has {LIMIT + 1} bytes; at most {LIMIT} are taken"


def test_the_default_limit_refuses_an_announced_20_megabytes(directory: Path) -> None:
    """MAX_BODY unset: MAX_BATCH (1000) records of 16 KiB, 16,384,000 bytes."""
    environment = {"POSITION_STORE_TOKEN": TOKEN, "TRANSFORMER": "off"}
    running = RunningService(directory, PACKAGE, environment).start()
    try:
        refused = announced(running.port, f"{STORE}/records/batch", 20_000_000, WRITE)
        assert refused.status == 413 and refused.closed
        assert refused.body["detail"] == "the body has 20000000 bytes; at most 16384000 are taken"
        status, _, _ = request("POST", f"{running.url}{STORE}/records", one(0))
        assert status == 201
    finally:
        running.stop()


def test_a_websocket_message_over_64_kib_closes_the_subscription(limited) -> None:
    frames = Frames(websocket_url(limited.url, f"{STORE}/records"), {"Accept": "application/json"})
    try:
        frames.connection.send("x" * 2**16)  # at the limit: read and dropped
        record = request("POST", f"{limited.url}{STORE}/records", one(0))[2]["id"]
        assert [f["id"] for f in frames.json(1)] == [record]
        frames.connection.send("x" * (2**16 + 1))
        assert frames.closed.wait(30)
        with pytest.raises(websockets.ConnectionClosed) as closed:
            frames.connection.recv(timeout=30)
        assert closed.value.rcvd is not None and closed.value.rcvd.code == 1009
    finally:
        frames.close()
