"""Subscriptions of the generated services (R0.12-R0.17 and R1.8 of the
Linked Data requirements, docs/services.md), through
uvicorn as deployed: a GET of a collection with ``Upgrade: websocket`` (the real
``websockets`` client) pushes each new record as one text frame, in id order, the JSON
frame being exactly what a GET of the record answers; ``after_id`` first sends the
stored records after it, never one twice; ``Upgrade: callback`` with ``Callback:``
stores a subscription that posts each new record to a receiver in the test process,
retrying with back-off, and survives a restart and a kill -9. The subscriptions are
listed (LDP container, RDF) and cancelled with DELETE. A record reaches its
subscribers within 50 ms (p99) of its commit, also when another process commits it."""

from __future__ import annotations

import itertools
import subprocess
import sys
import threading
import time
import urllib.request
from pathlib import Path

import pytest
import websockets
from pyshacl import validate
from rdflib import RDF, Graph, Namespace, URIRef

from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import TOKEN, RunningService, request, wait_for, write_files
from support.subscription_clients import Frames, Receiver, websocket_url

HYBRIT = Namespace("https://hybr-it-projekt.de/ns/hybr-it#")
PACKAGE = "position_store_service"
STORE = "/PositionStore"


@pytest.fixture(scope="module")
def directory(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = write_files(service.generate(product()), tmp_path_factory.mktemp("subscriptions"))
    return root / "services" / "PositionStore"


def _service(directory: Path, **env: str) -> RunningService:
    environment = {
        "POSITION_STORE_TOKEN": TOKEN,
        "POSITION_STORE_TRANSFORM_PERIOD": "0.05",
        "POSITION_STORE_CALLBACK_HOSTS": "127.0.0.1",
        **env,
    }
    return RunningService(directory, PACKAGE, environment)


@pytest.fixture(scope="module")
def positions(directory: Path):  # type: ignore[no-untyped-def]
    running = _service(directory).start()
    yield running
    running.stop()


def record(robot: str, i: int, key: str | None = None) -> dict:
    posted = {"robot": robot, "timestamp": 1e6 + i, "data": {"lat": 3600.0 * i, "lon": 0.0}}
    if key is not None:
        posted["key"] = key
    return posted


def post(url: str, records: list[dict]) -> list[int]:
    status, _, body = request("POST", f"{url}{STORE}/records/batch", {"records": records})
    assert status == 201, body
    return body["ids"]


def get_bytes(url: str, accept: str) -> bytes:
    req = urllib.request.Request(url, headers={"Accept": accept})
    with urllib.request.urlopen(req, timeout=10) as answer:
        return answer.read()


def test_a_websocket_pushes_each_new_record_as_a_get_answers_it(positions) -> None:
    frames = Frames(
        websocket_url(positions.url, f"{STORE}/records"), {"Accept": "application/json"}
    )
    try:
        posted: list[int] = []
        writers = [
            threading.Thread(
                target=lambda n=n: posted.extend(
                    post(positions.url, [record(f"ws{n}", i) for i in range(n % 3 + 1)])
                )
            )
            for n in range(12)
        ]
        for writer in writers:
            writer.start()
        for writer in writers:
            writer.join()
        texts = [text for _, text in frames.take(len(posted))]
        assert frames.nothing_more()
    finally:
        frames.close()
    ids = [int(text.split(",", 1)[0].removeprefix('{"id":')) for text in texts]
    assert ids == sorted(posted)  # each new record once, in id order
    for record_id, text in zip(ids, texts, strict=True):  # exactly the GET's JSON
        assert text.encode() == get_bytes(
            f"{positions.url}{STORE}/records/{record_id}", "application/json"
        )


def test_after_id_sends_the_stored_records_first_and_none_twice(positions) -> None:
    stored = post(positions.url, [record("after", i) for i in range(10)])
    after = stored[4]
    more: list[int] = []
    keep_posting = threading.Thread(
        target=lambda: [
            more.extend(post(positions.url, [record("after", 100 + i)])) for i in range(10)
        ]
    )
    keep_posting.start()  # records arrive while the subscription is being opened
    frames = Frames(
        websocket_url(positions.url, f"{STORE}/records", after_id=after),
        {"Accept": "application/json"},
    )
    try:
        keep_posting.join()
        expected = sorted(i for i in stored + more if i > after)
        others = wait_for(
            lambda: request("GET", f"{positions.url}{STORE}/records?after_id={after}&limit=1000")[
                2
            ]["items"]
        )
        everything = [item["id"] for item in others]  # other tests' records count too
        received = [item["id"] for item in frames.json(len(everything))]
        assert frames.nothing_more()
    finally:
        frames.close()
    assert received == everything and set(expected) <= set(received)


def test_turtle_frames_and_refined_collections(positions) -> None:
    turtle = Frames(websocket_url(positions.url, f"{STORE}/records"), {"Accept": "text/turtle"})
    refined = Frames(
        websocket_url(positions.url, f"{STORE}/PositionInDEG"), {"Accept": "application/json"}
    )
    try:
        ids = post(positions.url, [record("turtle", i) for i in range(3)])
        texts = [text for _, text in turtle.take(3)]
        degrees = refined.json(3)
    finally:
        turtle.close()
        refined.close()
    for record_id, text in zip(ids, texts, strict=True):
        assert text.encode() == get_bytes(
            f"{positions.url}{STORE}/records/{record_id}", "text/turtle"
        )
        data = Graph().parse(data=text, format="turtle")
        assert URIRef(f"{positions.url}{STORE}/records/{record_id}") in set(data.subjects())
    assert [d["raw_id"] for d in degrees] == ids and [d["lat"] for d in degrees] == [0, 1, 2]


def test_upgrade_requests_that_open_nothing(positions) -> None:
    base = f"{positions.url}{STORE}/records"
    status, headers, body = request("GET", base, headers={"Upgrade": "websocket"})
    assert status == 426 and headers["upgrade"] == "websocket"  # no handshake
    for headers_, reason in [
        ({"Upgrade": "callback"}, "needs a Callback header"),
        ({"Upgrade": "callback", "Callback": "ftp://127.0.0.1/x"}, "only http and https"),
        ({"Upgrade": "callback", "Callback": "http://"}, "only http and https"),
        ({"Upgrade": "callback", "Callback": "http://10.0.0.1/x"}, "a private address"),
        ({"Upgrade": "callback", "Callback": "http://a@127.0.0.1/"}, "user information"),
    ]:
        status, _, body = request("GET", base, headers=headers_)
        assert status == 400 and reason in body["detail"], (headers_, body)
    status, headers, _ = request(
        "GET", base, token=None, headers={"Upgrade": "callback", "Callback": "http://127.0.0.1/"}
    )
    assert status == 401 and headers["www-authenticate"] == "Bearer"
    status, _, body = request("GET", base, headers={"Upgrade": "h2c"})  # ignored
    assert status == 200 and "items" in body
    for url, refusal in [
        (websocket_url(positions.url, f"{STORE}/records", after_id="x"), 400),
        (websocket_url(positions.url, f"{STORE}/records", after_id=2**63), 400),
    ]:
        with pytest.raises(websockets.InvalidStatus) as refused:
            Frames(url)
        assert refused.value.response.status_code == refusal
    with pytest.raises(websockets.InvalidStatus) as refused:
        Frames(websocket_url(positions.url, f"{STORE}/records"), {"Accept": "text/html"})
    assert refused.value.response.status_code == 406


def test_websockets_need_the_token_where_reads_do(directory: Path, tmp_path: Path) -> None:
    running = _service(
        directory,
        POSITION_STORE_PROTECT_READS="1",
        DATABASE_URL=f"sqlite:///{tmp_path}/protected.db",
    ).start()
    try:
        url = websocket_url(running.url, f"{STORE}/records")
        for headers in ({}, {"Authorization": "Bearer wrong"}):
            with pytest.raises(websockets.InvalidStatus) as refused:
                Frames(url, headers)
            assert refused.value.response.status_code == 401
        frames = Frames(url, {"Authorization": f"Bearer {TOKEN}", "Accept": "application/json"})
        try:
            (record_id,) = post(running.url, [record("secret", 1)])
            assert [f["id"] for f in frames.json(1)] == [record_id]
        finally:
            frames.close()
    finally:
        running.stop()


# The service, with the read of the newest id (where a subscription starts) made slow, as
# on a loaded machine: what a client writes once its connection is open must reach it.
SLOW_NEWEST = """
import asyncio, os, sys

sys.path.insert(0, os.getcwd())  # the service's folder, as for python -m
from position_store_service import __main__ as entry
from position_store_service.runtime import hub

read = hub.Hub.newest

async def slow(self, collection):
    await asyncio.sleep(0.5)
    return await read(self, collection)

hub.Hub.newest = slow
entry.main()
"""


def test_a_record_written_as_soon_as_the_websocket_is_open_is_pushed(
    directory: Path, tmp_path: Path
) -> None:
    (tmp_path / "slow_newest.py").write_text(SLOW_NEWEST, encoding="utf-8")
    running = _service(directory, DATABASE_URL=f"sqlite:///{tmp_path}/open.db")
    running.command = [sys.executable, str(tmp_path / "slow_newest.py")]
    running.start()
    try:
        url = websocket_url(running.url, f"{STORE}/records")
        frames = Frames(url, {"Accept": "application/json"})
        try:
            (record_id,) = post(running.url, [record("eager", 1)])
            assert [f["id"] for f in frames.json(1, timeout=10)] == [record_id]
        finally:
            frames.close()
    finally:
        running.stop()


def test_a_transformer_of_its_own_feeds_the_subscribers(directory: Path, tmp_path: Path) -> None:
    env = {"DATABASE_URL": f"sqlite:///{tmp_path}/worker.db", "TRANSFORMER": "off"}
    running = _service(directory, **env).start()
    worker = subprocess.Popen(
        [sys.executable, "-m", f"{PACKAGE}.transformer"],
        cwd=directory,
        env=running.env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        frames = Frames(
            websocket_url(running.url, f"{STORE}/PositionInDEG", after_id=0),
            {"Accept": "application/json"},
        )
        ids = post(running.url, [record("worker", i) for i in range(5)])
        assert [f["raw_id"] for f in frames.json(5)] == ids
        frames.close()
    finally:
        worker.terminate()
        worker.wait(10)
        running.stop()


def _subscribe(
    url: str, receiver: Receiver, collection: str = "records", accept: str = "application/json"
) -> dict:
    """The subscription as JSON (its 201 answer comes as ``accept`` asks: Turtle for a
    subscription of Turtle records)."""
    req = urllib.request.Request(
        f"{url}{STORE}/{collection}",
        headers={
            "Upgrade": "callback",
            "Callback": receiver.url,
            "Accept": accept,
            "Authorization": f"Bearer {TOKEN}",
        },
    )
    with urllib.request.urlopen(req, timeout=10) as answer:
        assert answer.status == 201
        location = answer.headers["Location"]
        assert answer.headers["Content-Type"].startswith(accept)
    status, _, body = request("GET", url + location)
    assert status == 200 and body["href"] == location == f"{STORE}/subscriptions/{body['id']}"
    return body


def test_callbacks_post_each_new_record_and_are_listed_and_cancelled(positions) -> None:
    as_json, as_turtle = Receiver(), Receiver()
    try:
        first = _subscribe(positions.url, as_json)
        second = _subscribe(positions.url, as_turtle, "PositionInDEG", accept="text/turtle")
        assert (first["type"], first["media_type"]) == ("callback", "application/json")
        ids = post(positions.url, [record("hooked", i) for i in range(4)])
        bodies = as_json.take(4)
        assert [b for _, _, b in bodies] == [
            get_bytes(f"{positions.url}{STORE}/records/{i}", "application/json") for i in ids
        ]
        assert all(t == "application/json; charset=utf-8" for _, t, _ in bodies)
        refined = as_turtle.take(4)
        assert all(t == "text/turtle; charset=utf-8" for _, t, _ in refined)
        Graph().parse(data=refined[0][2].decode(), format="turtle")

        listing = Graph().parse(
            data=get_bytes_token(f"{positions.url}{STORE}/subscriptions"), format="turtle"
        )
        container = URIRef(f"{positions.url}{STORE}/subscriptions")
        members = set(listing.objects(container, URIRef("http://www.w3.org/ns/ldp#contains")))
        mine = {URIRef(f"{positions.url}{STORE}/subscriptions/{s['id']}") for s in (first, second)}
        assert mine <= members
        one = URIRef(f"{positions.url}{STORE}/subscriptions/{first['id']}")
        assert set(listing.objects(one, RDF.type)) == {HYBRIT.Subscription, HYBRIT.WebCallback}
        assert str(listing.value(one, HYBRIT.callbackURL)) == as_json.url
        assert str(listing.value(one, HYBRIT.mediaType)) == "application/json"
        assert listing.value(one, HYBRIT.onResource) == URIRef(f"{positions.url}{STORE}/records")
        shapes = Graph().parse(
            data=get_bytes(f"{positions.url}{STORE}/blueprint", "text/turtle"), format="turtle"
        )
        conforms, _, report = validate(listing, shacl_graph=shapes)
        assert conforms, report

        assert request("DELETE", f"{positions.url}{first['href']}", token=None)[0] == 401
        assert request("DELETE", f"{positions.url}{first['href']}")[0] == 204
        assert request("DELETE", f"{positions.url}{first['href']}")[0] == 404
        assert request("GET", f"{positions.url}{first['href']}")[0] == 404
        listed = [
            s["id"] for s in request("GET", f"{positions.url}{STORE}/subscriptions")[2]["items"]
        ]
        assert first["id"] not in listed and second["id"] in listed
        post(positions.url, [record("hooked", 10)])
        as_turtle.take(1)
        time.sleep(0.3)
        assert as_json.received.empty()  # cancelled: nothing more
        assert request("DELETE", f"{positions.url}{second['href']}")[0] == 204
    finally:
        as_json.close()
        as_turtle.close()


def get_bytes_token(url: str) -> str:
    req = urllib.request.Request(url, headers={"Authorization": f"Bearer {TOKEN}"})
    with urllib.request.urlopen(req, timeout=10) as answer:
        return answer.read().decode()


def test_a_failing_receiver_is_retried_with_growing_pauses(positions) -> None:
    receiver = Receiver(answers=[500, 503, 500, 502])
    try:
        subscription = _subscribe(positions.url, receiver)
        ids = post(positions.url, [record("retry", 1), record("retry", 2)])
        bodies = receiver.take(2)
        assert [int(b.split(b",")[0].removeprefix(b'{"id":')) for _, _, b in bodies] == ids
        times = [t for t, _ in receiver.attempts]
        pauses = [b - a for a, b in itertools.pairwise(times[:4])]  # the failed tries
        assert all(later > earlier * 1.5 for earlier, later in itertools.pairwise(pauses)), pauses
        assert request("DELETE", f"{positions.url}{subscription['href']}")[0] == 204
    finally:
        receiver.close()


def test_callback_subscriptions_survive_a_restart_and_a_kill(
    directory: Path, tmp_path: Path
) -> None:
    running = _service(directory, DATABASE_URL=f"sqlite:///{tmp_path}/kept.db").start()
    receiver = Receiver()
    try:
        _subscribe(running.url, receiver)
        running.stop()
        running.start()
        first = post(running.url, [record("kept", 1)])
        ((_, _, body),) = receiver.take(1)
        assert body.startswith(f'{{"id":{first[0]},'.encode())
        running.kill()  # its lease lapses: the next process takes the subscription over
        running.start()
        second = post(running.url, [record("kept", 2)])
        # at least once: a record whose delivery the kill left unrecorded comes again
        seen = []
        while second[0] not in seen:
            ((_, _, body),) = receiver.take(1, timeout=30)
            seen.append(int(body.split(b",")[0].removeprefix(b'{"id":')))
        assert set(seen) <= {first[0], second[0]} and seen.count(second[0]) == 1
    finally:
        receiver.close()
        running.stop()
