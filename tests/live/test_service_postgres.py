"""The generated services on a real PostgreSQL server (a throw-away cluster made with
Debian's initdb): both case studies end to end, the kill -9 crash test, and replicas
sharing one database: each keyed record stored once, each raw and refined record
transformed once and pushed once, in id order, to a WebSocket subscriber."""

from __future__ import annotations

import math
import os
import shutil
import tempfile
import threading
from pathlib import Path

import psycopg
import pytest

from spl.dsl.tsm import language as tsm_language
from spl.generators.clients import generator as clients
from spl.generators.service import generator as service
from spl.resolver.architecture.product import ResolvedProduct

from support.service_models import PRODUCT_LINE, product
from support.service_runtime import (
    TOKEN,
    PostgresCluster,
    RunningService,
    crash_during_transformation,
    load_module,
    post_concurrently,
    post_in_batches,
    postgres_binaries,
    request,
    wait_for,
    write_files,
)
from support.subscription_clients import Frames, websocket_url

BINARIES = postgres_binaries()
# On a developer machine without Debian's postgresql the tests are skipped; CI installs
# it (.ci/run), so there a missing server is a failure, never a skip.
pytestmark = pytest.mark.skipif(
    BINARIES is None and not os.environ.get("CI"), reason="PostgreSQL binaries not installed"
)
POSTGRES_PRODUCT = ("DataAcquisition", "Follow", "Positions", "Postgres", "Storage")


@pytest.fixture(scope="module")
def cluster():  # type: ignore[no-untyped-def]
    base = Path(tempfile.mkdtemp(prefix="spl-pg-", dir="/tmp"))
    server = PostgresCluster(BINARIES, base).start()
    yield server
    server.stop()
    shutil.rmtree(base, ignore_errors=True)


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Path:
    resolved = product(features=POSTGRES_PRODUCT)
    files = {**service.generate(resolved), **clients.generate(resolved)}
    return write_files(files, tmp_path_factory.mktemp("bundle"))


def _service(
    bundle: Path, cluster: PostgresCluster, store: str, slug: str, **env: str
) -> RunningService:
    environment = {
        f"{slug.upper()}_TOKEN": TOKEN,
        f"{slug.upper()}_TRANSFORM_PERIOD": "0.05",
        "DATABASE_URL": cluster.dsn(),
        **env,
    }
    return RunningService(bundle / "services" / store, f"{slug}_service", environment)


def test_postgres_is_the_default_database_of_the_postgres_product(bundle: Path) -> None:
    settings = (bundle / "services/PositionStore/position_store_service/settings.py").read_text()
    assert "DEFAULT_DATABASE_URL = 'postgresql://spl@localhost:5432/spl'" in settings


def test_both_case_studies_on_postgres(bundle: Path, cluster: PostgresCluster) -> None:
    positions = _service(bundle, cluster, "PositionStore", "position_store").start()
    follow = _service(bundle, cluster, "FollowStore", "follow_store").start()
    try:
        writer = load_module(
            bundle / "clients/ros2/position_writer/position_writer/store_client.py", "pg_pw"
        )
        writer.StoreClient(positions.url, token=TOKEN).post(
            [
                writer.to_record("rover_1", 10.0 + i, {"lat": 3600.0 * i, "lon": 1800.0})
                for i in range(5)
            ]
        )
        reader = load_module(
            bundle / "clients/ros2/position_reader/position_reader/store_client.py", "pg_pr"
        )
        poller = reader.PollingReader(reader.StoreClient(positions.url))
        degrees: list[dict] = []
        wait_for(lambda: degrees.extend(poller.poll()) or len(degrees) >= 5)
        assert [(d["lat"], d["lon"]) for d in degrees] == [(float(i), 0.5) for i in range(5)]

        velocity = load_module(
            bundle / "clients/ros2/velocity_writer/velocity_writer/store_client.py", "pg_vw"
        )
        velocity.StoreClient(follow.url, token=TOKEN).post(
            [
                velocity.to_record("ev3_a", t, {"vx": 0.1, "vy": 0.0, "va": 0.0})
                for t in (1.0, 3.5, 4.0)
            ]
        )
        commands_http = load_module(
            bundle / "clients/ros2/command_reader/command_reader/store_client.py", "pg_cr"
        )
        commands = commands_http.PollingReader(commands_http.StoreClient(follow.url))
        received: list[dict] = []
        wait_for(lambda: received.extend(commands.poll()) or len(received) >= 2)
        assert [c["duration"] for c in received] == [2.5, 0.5]
        assert all(math.isclose(c["vx"], 0.1) for c in received)
    finally:
        positions.stop()
        follow.stop()


def test_kill_9_during_transformation_on_postgres(bundle: Path, cluster: PostgresCluster) -> None:
    total = 8000
    running = _service(
        bundle,
        cluster,
        "PositionStore",
        "position_store",
        TRANSFORMER="off",
        POSITION_STORE_TRANSFORM_PERIOD="0.02",
    ).start()
    records = [
        {"robot": f"crash_{i % 4}", "timestamp": 1e6 + i, "data": {"lat": 7200.0, "lon": float(i)}}
        for i in range(total)
    ]
    post_in_batches(f"{running.url}/PositionStore/records/batch", records)
    running.kill()

    def count_refined() -> int:
        with psycopg.connect(cluster.dsn()) as conn:
            return conn.execute(
                "SELECT count(*) FROM position_store_position_in_deg WHERE robot LIKE 'crash_%'"
            ).fetchone()[0]

    running.env["TRANSFORMER"] = "embedded"
    try:
        crash_during_transformation(running, count_refined, total)
    finally:
        running.stop()
    with psycopg.connect(cluster.dsn()) as conn:
        rows = conn.execute(
            "SELECT d.lat, d.lon, r.document FROM position_store_position_in_deg d "
            "JOIN position_store_raw r ON r.id = d.raw_id WHERE d.robot LIKE 'crash_%'"
        ).fetchall()
    assert len(rows) == total
    assert sorted(r[1] for r in rows) == [i / 3600.0 for i in range(total)]
    assert all(r[0] == 2.0 and r[2]["lon"] / 3600.0 == r[1] for r in rows)


def test_concurrent_posts_get_their_own_ids_on_postgres(
    bundle: Path, cluster: PostgresCluster
) -> None:
    """Groups of requests in one transaction, their ids read back from psycopg's
    pipeline in order: every 201 names the row of its own record."""
    running = _service(bundle, cluster, "PositionStore", "position_store", TRANSFORMER="off")
    running.start()
    try:
        answered = post_concurrently(f"{running.url}/PositionStore", per_writer=30, prefix="pg")
    finally:
        running.stop()
    with psycopg.connect(cluster.dsn()) as conn:
        rows = conn.execute(
            "SELECT id, robot, source_ts, document FROM position_store_raw WHERE robot LIKE 'pg%'"
        ).fetchall()
    stored = {row[0]: row[1:] for row in rows}
    assert len(answered) == len(stored) == 8 * (24 + 6 * 3)
    assert all(
        stored[i] == (record["robot"], record["timestamp"], record["data"])
        for i, record in answered.items()
    )


def test_replicas_store_each_key_once_and_push_each_record_once_in_order(
    bundle: Path, cluster: PostgresCluster
) -> None:
    """Three replicas, each with its own transformer, on one database. Six writers send
    every keyed batch twice, to two replicas (a retry after a lost answer): both answers
    name the same records, each stored once; one subscriber of the raw records and one
    of the refined ones (on other replicas) get each record exactly once, in id order."""
    with psycopg.connect(cluster.dsn()) as conn:
        conn.execute("SELECT 1")
    replicas = [_service(bundle, cluster, "PositionStore", "position_store").start()]
    replicas += [
        _service(bundle, cluster, "PositionStore", "position_store").start() for _ in range(2)
    ]
    with psycopg.connect(cluster.dsn()) as conn:
        raw_after = conn.execute("SELECT coalesce(max(id), 0) FROM position_store_raw").fetchone()[
            0
        ]
        refined_after = conn.execute(
            "SELECT coalesce(max(id), 0) FROM position_store_position_in_deg"
        ).fetchone()[0]
    raw_frames = Frames(
        websocket_url(replicas[1].url, "/PositionStore/records", after_id=raw_after),
        {"Accept": "application/json"},
    )
    refined_frames = Frames(
        websocket_url(replicas[2].url, "/PositionStore/PositionInDEG", after_id=refined_after),
        {"Accept": "application/json"},
    )
    answers: dict[str, set[int]] = {}
    failures: list = []

    def write(n: int) -> None:
        for i in range(10):
            records = [
                {
                    "robot": f"replica_{n}",
                    "timestamp": 1e7 + i * 3 + j,
                    "data": {"lat": 3600.0 * j, "lon": 0.0},
                    "key": f"b{i}.{j}",
                }
                for j in range(3)
            ]
            for target in (i % 3, (i + n) % 3 if (i + n) % 3 != i % 3 else (i + 1) % 3):
                status, _, body = request(
                    "POST",
                    f"{replicas[target].url}/PositionStore/records/batch",
                    {"records": records},
                )
                if status != 201:
                    failures.append(body)
                    return
                for record, record_id in zip(records, body["ids"], strict=True):
                    answers.setdefault(f"{n}:{record['key']}", set()).add(record_id)

    writers = [threading.Thread(target=write, args=(n,)) for n in range(6)]
    try:
        for writer in writers:
            writer.start()
        for writer in writers:
            writer.join()
        assert not failures, failures[:2]
        assert len(answers) == 180 and all(len(ids) == 1 for ids in answers.values())
        expected = sorted(next(iter(ids)) for ids in answers.values())
        raw = [frame["id"] for frame in raw_frames.json(180, timeout=60)]
        refined = refined_frames.json(180, timeout=60)
        assert raw_frames.nothing_more(0.5) and refined_frames.nothing_more(0.1)
    finally:
        raw_frames.close()
        refined_frames.close()
        for replica in replicas:
            replica.stop()
    assert raw == expected  # each record once, in id order
    refined_ids = [frame["id"] for frame in refined]
    assert refined_ids == sorted(set(refined_ids))
    assert sorted(frame["raw_id"] for frame in refined) == expected
    with psycopg.connect(cluster.dsn()) as conn:
        count, keys = conn.execute(
            "SELECT count(*), count(DISTINCT (robot, key)) FROM position_store_raw "
            "WHERE robot LIKE 'replica_%'"
        ).fetchone()
        transformed = conn.execute(
            "SELECT count(*) FROM position_store_position_in_deg WHERE robot LIKE 'replica_%'"
        ).fetchone()[0]
    assert count == keys == transformed == 180


LONG_STORE = "Readings" + "x" * 64  # its table and index names pass PostgreSQL's 63 bytes


def _clashing_names() -> ResolvedProduct:
    """Two stores ``PositionStore`` in two cloud containers and a store whose derived
    table and index names are longer than PostgreSQL keeps, all in one database."""
    types = (PRODUCT_LINE / "data.tsm").read_text(encoding="utf-8").split("cloud container")[0]
    store = """    store {name} {{
        raw PositionInSecond
        refined PositionInDEG by SecondToDEG every 5 s
    }}
"""
    text = (
        types
        + "cloud container FieldCloud {\n"
        + store.format(name="PositionStore")
        + store.format(name=LONG_STORE)
        + "}\ncloud container LabCloud {\n"
        + store.format(name="PositionStore")
        + "}\n"
    )
    return ResolvedProduct("clash", tsm_language.parse_text(text, "clash.tsm"), ())


def test_stores_of_one_name_and_long_names_share_one_database(
    cluster: PostgresCluster, tmp_path: Path
) -> None:
    root = write_files(service.generate(_clashing_names()), tmp_path)
    slugs = {
        "FieldCloud_PositionStore": "field_cloud_position_store",
        "LabCloud_PositionStore": "lab_cloud_position_store",
        LONG_STORE: "readings" + "x" * 64,
    }
    running = [_service(root, cluster, key, slug).start() for key, slug in slugs.items()]
    try:
        for service_, key in zip(running, slugs, strict=True):
            body = {"records": [{"robot": "r", "timestamp": 1.0,
                                 "data": {"lat": 3600.0, "lon": 0.0}}]}  # fmt: skip
            assert request("POST", f"{service_.url}/{key}/records/batch", body)[0] == 201
        for service_, key in zip(running, slugs, strict=True):
            items = wait_for(
                lambda s=service_, k=key: (
                    request("GET", f"{s.url}/{k}/PositionInDEG?from=0&to=10")[2]["items"] or None
                )
            )
            assert [(i["robot"], i["lat"]) for i in items] == [("r", 1.0)]  # its own, once
    finally:
        for service_ in running:
            service_.stop()
    with psycopg.connect(cluster.dsn()) as conn:
        names = [row[0] for row in conn.execute(
            "SELECT relname FROM pg_class WHERE relname LIKE '%raw%'")]  # fmt: skip
    assert len(names) == len(set(names)) and max(len(n) for n in names) <= 63
    assert {"field_cloud_position_store_raw", "lab_cloud_position_store_raw"} <= set(names)


def test_the_readiness_route_fails_while_the_database_is_gone(bundle: Path) -> None:
    """The root the readiness probe GETs makes a round trip to the database: with the
    database gone it is a 500 (no traffic routed to the service), while /openapi.json,
    the liveness probe's, still answers (the service is not restarted for it)."""
    base = Path(tempfile.mkdtemp(prefix="spl-pg-", dir="/tmp"))
    own = PostgresCluster(BINARIES, base).start()
    running = _service(bundle, own, "PositionStore", "position_store").start()
    try:
        assert request("GET", f"{running.url}/", token=None)[0] == 200
        own.stop()
        assert request("GET", f"{running.url}/", token=None)[0] == 500
        assert request("GET", f"{running.url}/openapi.json", token=None)[0] == 200
    finally:
        running.stop()
        own.stop()
        shutil.rmtree(base, ignore_errors=True)
