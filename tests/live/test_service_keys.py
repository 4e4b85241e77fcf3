"""Idempotent writes: a posted record may carry a ``key`` (1-128 of [A-Za-z0-9_.:-]);
the store keeps one record per robot and key, and a record whose robot and key are
stored already is not stored again: the answer names the stored record in its place
(single post: id and Location; batch: ``ids`` at its position). Also when the same
batch is sent by many writers at once, and on a database an earlier version made."""

from __future__ import annotations

import sqlite3
import threading
from pathlib import Path

import pytest

from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import TOKEN, RunningService, request, write_files

PACKAGE = "position_store_service"
STORE = "/PositionStore"


@pytest.fixture(scope="module")
def directory(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = write_files(service.generate(product()), tmp_path_factory.mktemp("keys"))
    return root / "services" / "PositionStore"


@pytest.fixture(scope="module")
def positions(directory: Path):  # type: ignore[no-untyped-def]
    running = RunningService(
        directory, PACKAGE, {"POSITION_STORE_TOKEN": TOKEN, "TRANSFORMER": "off"}
    ).start()
    yield running
    running.stop()


def record(robot: str, i: int, key: str | None = None) -> dict:
    posted = {"robot": robot, "timestamp": 1e6 + i, "data": {"lat": float(i), "lon": 0.0}}
    if key is not None:
        posted["key"] = key
    return posted


def stored(url: str, robot: str) -> list[dict]:
    return request("GET", f"{url}{STORE}/records?robot={robot}&limit=1000")[2]["items"]


def test_a_record_sent_again_with_its_key_is_stored_once(positions) -> None:
    base = f"{positions.url}{STORE}"
    status, headers, first = request("POST", f"{base}/records", record("once", 1, "s-1"))
    assert status == 201
    again = record("once", 1, "s-1")
    again["data"]["lat"] = 99.0  # what is stored is the first record, whatever comes again
    status, headers_again, second = request("POST", f"{base}/records", again)
    assert status == 201 and second == first
    assert headers_again["location"] == headers["location"] == first["href"]
    # a batch: a stored key, a new one, the new one again, and records without keys
    batch = [
        record("once", 2, "s-2"),
        record("once", 1, "s-1"),
        record("once", 3),
        record("once", 2, "s-2"),
        record("once", 3),
    ]
    status, _, answer = request("POST", f"{base}/records/batch", {"records": batch})
    assert status == 201
    ids = answer["ids"]
    assert ids[1] == first["id"] and ids[3] == ids[0] and len(set(ids)) == 4
    assert answer["hrefs"] == [f"{STORE}/records/{i}" for i in ids]
    rows = stored(positions.url, "once")
    assert sorted(r["id"] for r in rows) == sorted(set(ids))
    assert {r["id"]: r["key"] for r in rows}[first["id"]] == "s-1"
    assert {r["id"]: r["data"]["lat"] for r in rows}[first["id"]] == 1.0
    # the key is the robot's: another robot may use the same one
    status, _, other = request("POST", f"{base}/records", record("twice", 1, "s-1"))
    assert status == 201 and other["id"] != first["id"]


@pytest.mark.parametrize("key", ["", "x" * 129, "a b", "ä", "k/1", "k?", 7, None])
def test_keys_are_refused_with_the_reason(positions, key) -> None:
    posted = record("bad_key", 1)
    posted["key"] = key
    status, _, answer = request("POST", f"{positions.url}{STORE}/records", posted)
    if key is None:  # no key, as without the field
        assert status == 201
        return
    assert status == 400 and answer["detail"][0]["where"] == "body/key", answer


def test_longest_key_and_every_allowed_character(positions) -> None:
    for key in ("x" * 128, "AZaz09_.:-"):
        status, _, answer = request(
            "POST", f"{positions.url}{STORE}/records", record("good_key", len(key), key)
        )
        assert status == 201, answer


def test_the_same_batch_from_many_writers_at_once_is_stored_once(positions) -> None:
    batch = {"records": [record("racer", i, f"race-{i}") for i in range(20)]}
    answers: list[list[int]] = []
    lock = threading.Lock()

    def send() -> None:
        status, _, answer = request("POST", f"{positions.url}{STORE}/records/batch", batch)
        assert status == 201
        with lock:
            answers.append(answer["ids"])

    threads = [threading.Thread(target=send) for _ in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert len(answers) == 8 and all(a == answers[0] for a in answers)
    assert sorted(r["id"] for r in stored(positions.url, "racer")) == sorted(answers[0])


def test_a_database_of_an_earlier_version_gets_the_key(directory: Path, tmp_path: Path) -> None:
    database = tmp_path / "old.db"
    env = {
        "POSITION_STORE_TOKEN": TOKEN,
        "TRANSFORMER": "off",
        "DATABASE_URL": f"sqlite:///{database}",
    }
    running = RunningService(directory, PACKAGE, env).start()
    running.stop()
    with sqlite3.connect(database) as conn:  # as the service made it before keys
        conn.execute("DROP INDEX position_store_raw_robot_key")
        conn.execute("ALTER TABLE position_store_raw DROP COLUMN key")
        conn.execute(
            "INSERT INTO position_store_raw (robot, source_ts, received_ts, document) "
            "VALUES ('old', 1.0, 1.0, '{\"lat\": 1.0, \"lon\": 2.0}')"
        )
    running.start()
    try:
        for _ in range(2):
            status, _, answer = request(
                "POST", f"{running.url}{STORE}/records", record("old", 2, "k")
            )
            assert status == 201 and answer["id"] == 2
        assert [(r["id"], r["key"]) for r in stored(running.url, "old")] == [(1, None), (2, "k")]
    finally:
        running.stop()
