"""How the generated service stores posted records (runtime/ingest.py): many requests per
transaction (group commit) without mixing them up, each request all or nothing, a
record answered 201 in the database also after kill -9, the token checked before
the body, and the write endpoints documented in OpenAPI as before (bodies over the
limit: test_service_body_limits.py)."""

from __future__ import annotations

import asyncio
import json
import sqlite3
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest
from sqlalchemy import event

from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import (
    TOKEN,
    RunningService,
    post_concurrently,
    request,
    wait_for,
    write_files,
)

PACKAGE = "position_store_service"


@pytest.fixture(scope="module")
def directory(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = write_files(service.generate(product()), tmp_path_factory.mktemp("ingest"))
    return root / "services" / "PositionStore"


@pytest.fixture(scope="module")
def positions(directory: Path):  # type: ignore[no-untyped-def]
    running = RunningService(directory, PACKAGE, {"POSITION_STORE_TOKEN": TOKEN}).start()
    yield running
    running.stop()


def _stored(database: Path) -> dict[int, tuple[str, float, str]]:
    with sqlite3.connect(f"file:{database}?mode=ro", uri=True, timeout=30) as conn:
        rows = conn.execute("SELECT id, robot, source_ts, document FROM position_store_raw")
        return {row[0]: row[1:] for row in rows}


def _same(record: dict, stored: tuple[str, float, Any]) -> bool:
    robot, timestamp, document = stored
    if isinstance(document, str):
        document = json.loads(document)
    return (robot, timestamp, document) == (record["robot"], record["timestamp"], record["data"])


def test_concurrent_posts_each_get_the_id_of_their_own_record(positions, directory) -> None:
    answered = post_concurrently(f"{positions.url}/PositionStore", writers=8, per_writer=40)
    assert len(answered) == 8 * (32 + 8 * 3)
    stored = _stored(directory / "position_store.db")
    assert all(_same(record, stored[i]) for i, record in answered.items())
    status, _, one = request("GET", f"{positions.url}/PositionStore/records/{max(answered)}")
    assert status == 200 and one["data"] == answered[max(answered)]["data"]


def test_the_token_is_checked_before_the_body(positions) -> None:
    base = f"{positions.url}/PositionStore"
    bad = {"robot": "r", "timestamp": "soon", "data": {}}
    for path, body in [("/records", bad), ("/records/batch", {"records": [bad]})]:
        status, headers, answer = request("POST", base + path, body, token=None)
        assert (status, answer["detail"]) == (401, "missing bearer token")
        assert headers["www-authenticate"] == "Bearer"
        assert request("POST", base + path, body, token="wrong")[0] == 401
        status, _, answer = request("POST", base + path, body)
        assert status == 400 and {r["where"].split("/")[0] for r in answer["detail"]} == {"body"}


def test_a_body_that_is_not_json_is_refused_with_the_reason(positions) -> None:
    base = f"{positions.url}/PositionStore"
    good = b'{"robot": "r", "timestamp": 1.0, "data": {"lat": 1.0, "lon": 2.0}}'
    for content_type in ("text/plain", "application/x-www-form-urlencoded"):
        status, _, answer = request(
            "POST", f"{base}/records", raw=good, headers={"Content-Type": content_type}
        )
        assert status == 400 and answer["detail"][0]["where"] == "body", answer
    status, _, answer = request("POST", f"{base}/records", raw=b"")
    assert status == 400 and answer["detail"][0]["where"] == "body"
    status, _, answer = request(
        "POST", f"{base}/records", raw=good, headers={"Content-Type": "application/vnd.robot+json"}
    )
    assert status == 201, answer


def test_the_write_endpoints_are_documented_as_before(positions) -> None:
    openapi = request("GET", positions.url + "/openapi.json")[2]
    paths = openapi["paths"]
    for path, model in [
        ("/PositionStore/records", "RawRecordIn"),
        ("/PositionStore/records/batch", "RawBatchIn"),
    ]:
        post = paths[path]["post"]
        schema = post["requestBody"]["content"]["application/json"]["schema"]
        assert schema == {"$ref": f"#/components/schemas/{model}"}
        assert post["requestBody"]["required"] is True
        assert post["security"] == [{"bearer": []}]  # the token, as a security scheme
        assert "parameters" not in post
        assert openapi["components"]["securitySchemes"]["bearer"]["scheme"] == "bearer"
        # the service answers 400 with the reasons, never FastAPI's 422
        assert set(post["responses"]) == {"201", "400", "401", "406", "413", "500"}


def test_a_record_answered_201_is_stored_also_after_kill_9(tmp_path: Path) -> None:
    write_files(service.generate(product()), tmp_path)
    directory = tmp_path / "services" / "PositionStore"
    running = RunningService(
        directory, PACKAGE, {"POSITION_STORE_TOKEN": TOKEN, "TRANSFORMER": "off"}
    ).start()
    answered: dict[int, dict] = {}
    writers = threading.Thread(
        target=post_concurrently,
        kwargs={
            "base": f"{running.url}/PositionStore",
            "writers": 8,
            "per_writer": 100_000,
            "answered": answered,
        },
    )
    writers.start()
    try:
        wait_for(lambda: len(answered) >= 300, timeout=60, interval=0.01)
    finally:
        running.kill()  # posts are in flight: some were committed, some not yet
        writers.join(60)
    assert not writers.is_alive()
    stored = _stored(directory / "position_store.db")
    missing = [i for i, record in answered.items() if not _same(record, stored.get(i, ("", 0, {})))]
    assert not missing, f"{len(missing)} of {len(answered)} records answered 201 are lost"


# --- the writer in process: one transaction per turn of the event loop -------------


@pytest.fixture
def ingest(tmp_path: Path):  # type: ignore[no-untyped-def]
    """The generated ``database`` module and its runtime's ``ingest``, imported in this
    process from the generated service (the runtime as the service ships it)."""
    write_files(service.generate(product()), tmp_path)
    sys.path.insert(0, str(tmp_path / "services" / "PositionStore"))
    try:
        from position_store_service import database
        from position_store_service.runtime import ingest

        yield database, ingest, f"sqlite:///{tmp_path}/writer.db"
    finally:
        sys.path.pop(0)
        for name in [n for n in sys.modules if n.split(".")[0] == PACKAGE]:
            del sys.modules[name]


def _rows(robot: str, count: int) -> list[dict[str, Any]]:
    return [
        {
            "robot": robot,
            "source_ts": float(i),
            "received_ts": 0.0,
            "document": {"lat": float(i), "lon": 0.5},
        }
        for i in range(count)
    ]


async def _with_writer(ingest, url: str, work, setup=None):  # type: ignore[no-untyped-def]
    database, module, _ = ingest
    engine = database.create(url)
    commits: list[float] = []
    event.listen(engine, "commit", lambda _conn: commits.append(time.monotonic()))
    if setup is not None:
        with engine.begin() as conn:
            conn.exec_driver_sql(setup)
    from position_store_service.model import RAW_KEY_WHERE, raw_records

    writer = module.RecordWriter(engine, database.write_turns, raw_records, RAW_KEY_WHERE).start()
    try:
        result = await work(writer)
    finally:
        writer.close()
    with engine.connect() as conn:
        stored = {
            row.id: row
            for row in conn.exec_driver_sql(
                "SELECT id, robot, source_ts, document FROM position_store_raw"
            )
        }
    engine.dispose()
    return result, stored, len(commits)


def test_requests_of_one_turn_share_one_transaction(ingest) -> None:
    async def work(writer):  # type: ignore[no-untyped-def]
        return await asyncio.gather(
            writer.store(_rows("a", 1)), writer.store(_rows("b", 3)), writer.store(_rows("c", 1))
        )

    (a, b, c), stored, commits = asyncio.run(_with_writer(ingest, ingest[2], work))
    assert commits == 1
    assert len(a) == len(c) == 1 and len(b) == 3 and len({*a, *b, *c}) == 5
    assert [stored[i].robot for i in a + b + c] == ["a", "b", "b", "b", "c"]
    assert [stored[i].source_ts for i in b] == [0.0, 1.0, 2.0]  # ids in the rows' order


def test_a_refused_row_fails_only_its_own_request(ingest) -> None:
    refuse = (
        "CREATE TRIGGER refuse BEFORE INSERT ON position_store_raw "
        "WHEN NEW.robot = 'refused' BEGIN SELECT RAISE(ABORT, 'refused robot'); END"
    )

    async def work(writer):  # type: ignore[no-untyped-def]
        return await asyncio.gather(
            writer.store(_rows("a", 2)),
            writer.store(_rows("ok", 1) + _rows("refused", 1)),
            writer.store(_rows("c", 1)),
            return_exceptions=True,
        )

    (a, refused, c), stored, _ = asyncio.run(_with_writer(ingest, ingest[2], work, refuse))
    assert isinstance(refused, sqlite3.IntegrityError) and "refused robot" in str(refused)
    assert sorted(row.robot for row in stored.values()) == ["a", "a", "c"]  # no "ok" either
    assert [stored[i].robot for i in a + c] == ["a", "a", "c"]


def test_closing_the_writer_stores_what_was_handed_over(ingest) -> None:
    async def work(writer):  # type: ignore[no-untyped-def]
        tasks = [asyncio.ensure_future(writer.store(_rows(f"r{n}", 2))) for n in range(4)]
        await asyncio.sleep(0)  # the requests wait for the writer
        writer.close()
        return await asyncio.gather(*tasks)

    ids, stored, _ = asyncio.run(_with_writer(ingest, ingest[2], work))
    assert sorted(i for pair in ids for i in pair) == sorted(stored)
    assert len(stored) == 8


def test_a_taken_write_lock_never_blocks_the_event_loop(ingest, tmp_path: Path) -> None:
    """Another connection holds SQLite's write lock: the posts wait in the writer
    thread, the event loop goes on turning, and the posts are stored once it is free."""
    database = tmp_path / "writer.db"

    async def work(writer):  # type: ignore[no-untyped-def]
        holder = sqlite3.connect(database, isolation_level=None)
        holder.execute("BEGIN IMMEDIATE")
        ticks = 0
        posts = asyncio.gather(writer.store(_rows("a", 2)), writer.store(_rows("b", 1)))
        started = time.monotonic()
        while time.monotonic() - started < 0.3:
            await asyncio.sleep(0.01)
            ticks += 1
        assert not posts.done()
        holder.execute("COMMIT")
        holder.close()
        return ticks, await posts

    (ticks, (a, b)), stored, _ = asyncio.run(_with_writer(ingest, ingest[2], work))
    assert ticks >= 10  # the loop turned all along (at most 30 turns in 0.3 s)
    assert [stored[i].robot for i in a + b] == ["a", "a", "b"]


def test_the_writer_thread_checkpoints_what_the_event_loop_wrote(ingest, tmp_path: Path) -> None:
    """A checkpoint syncs the disk: the event loop's connection leaves it to the writer
    thread, which copies the log into the database file once a second."""
    database = tmp_path / "writer.db"

    async def work(writer):  # type: ignore[no-untyped-def]
        await writer.store(_rows("warm", 1))
        in_loop = writer.connections[True].connection.dbapi_connection
        assert in_loop.execute("PRAGMA wal_autocheckpoint").fetchone() == (0,)
        size = database.stat().st_size
        for n in range(50):
            await writer.store(_rows(f"r{n}", 20))
        started = time.monotonic()
        while database.stat().st_size == size and time.monotonic() - started < 10:
            await asyncio.sleep(0.05)
        return database.stat().st_size - size

    grown, stored, _ = asyncio.run(_with_writer(ingest, ingest[2], work))
    assert grown > 0 and len(stored) == 1001


def test_waiting_posts_write_before_the_transformer_s_next_step(ingest) -> None:
    turns = ingest[0].WriteTurns()
    order: list[str] = []
    step_done = threading.Event()

    def transformer_step(name: str, hold: threading.Event | None) -> None:
        with turns.transformer():
            order.append(name)
            if hold is not None:
                hold.wait(10)

    def posts() -> None:
        with turns.posts():
            order.append("posts")

    first = threading.Thread(target=transformer_step, args=("step 1", step_done))
    first.start()
    wait_for(lambda: order == ["step 1"])
    assert not turns.try_posts()  # the event loop never waits: it hands over
    writer = threading.Thread(target=posts)
    writer.start()
    wait_for(lambda: turns.posts_waiting == 1)
    second = threading.Thread(target=transformer_step, args=("step 2", None))
    second.start()
    step_done.set()
    for thread in (first, writer, second):
        thread.join(10)
    assert order == ["step 1", "posts", "step 2"]
    assert turns.try_posts()
    turns.release()


def test_the_transformer_writes_only_in_its_turn(ingest) -> None:
    """While the posts of this process hold the turn, no transformer step starts."""
    database, _, url = ingest
    from position_store_service import transformer
    from position_store_service.model import REFINEMENTS
    from position_store_service.runtime.transformer import Transformer

    async def work(writer):  # type: ignore[no-untyped-def]
        await writer.store(_rows("busy", 1200))
        with database.write_turns.posts():
            run = threading.Thread(
                target=Transformer(
                    writer.engine, transformer.STORE, database.write_turns
                ).run_refinement,
                args=(REFINEMENTS[0],),
            )
            run.start()
            run.join(0.5)
            waited = run.is_alive()
            with writer.engine.connect() as conn:
                early = conn.exec_driver_sql(
                    "SELECT count(*) FROM position_store_position_in_deg"
                ).scalar_one()
        run.join(60)
        with writer.engine.connect() as conn:
            done = conn.exec_driver_sql(
                "SELECT count(*) FROM position_store_position_in_deg"
            ).scalar_one()
        return waited, early, done

    (waited, early, done), _, _ = asyncio.run(_with_writer(ingest, url, work))
    assert waited and early == 0 and done == 1200
