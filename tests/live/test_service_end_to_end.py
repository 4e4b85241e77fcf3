"""Both case studies of the data-acquisition paper end to end, on SQLite: the services
generated from
product_lines/data_acquisition/data.tsm run under uvicorn, the generated writer's HTTP
module posts, the transformer runs, the generated reader's HTTP module reads back."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from spl.generators.clients import generator as clients
from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import (
    TOKEN,
    RunningService,
    load_module,
    request,
    wait_for,
    write_files,
)

ARC_SECONDS = [(128520.0, 502200.0), (128523.6, 502203.6), (-3600.0, 648000.0)]


@pytest.fixture(scope="module")
def bundle(tmp_path_factory: pytest.TempPathFactory) -> Path:
    resolved = product()
    files = {**service.generate(resolved), **clients.generate(resolved)}
    return write_files(files, tmp_path_factory.mktemp("bundle"))


def _start(bundle: Path, store: str, slug: str) -> RunningService:
    env = {
        f"{slug.upper()}_TOKEN": TOKEN,
        f"{slug.upper()}_TRANSFORM_PERIOD": "0.1",
        "MAX_BATCH": "50",
    }
    return RunningService(bundle / "services" / store, f"{slug}_service", env).start()


@pytest.fixture(scope="module")
def positions(bundle: Path):  # type: ignore[no-untyped-def]
    running = _start(bundle, "PositionStore", "position_store")
    yield running
    running.stop()


@pytest.fixture(scope="module")
def follow(bundle: Path):  # type: ignore[no-untyped-def]
    running = _start(bundle, "FollowStore", "follow_store")
    yield running
    running.stop()


def client_module(bundle: Path, package: str):  # type: ignore[no-untyped-def]
    path = bundle / "clients" / "ros2" / package / package / "store_client.py"
    return load_module(path, f"client_{package}")


def test_positions_in_arc_seconds_come_back_in_degrees(bundle: Path, positions) -> None:
    writer_http = client_module(bundle, "position_writer")
    writer = writer_http.BatchingWriter(
        writer_http.StoreClient(positions.url, token=TOKEN), robot="rover_1", batch_size=2
    )
    for index, (lat, lon) in enumerate(ARC_SECONDS):
        assert writer.submit(1000.0 + index, {"lat": lat, "lon": lon})
    assert writer.flush(10)
    writer.close()
    assert writer.sent == 3 and writer.rejected == 0

    reader_http = client_module(bundle, "position_reader")
    reader = reader_http.PollingReader(reader_http.StoreClient(positions.url), robot="rover_1")
    received: list[dict] = []
    wait_for(lambda: received.extend(reader.poll()) or len(received) >= 3)
    assert [r["timestamp"] for r in received] == [1000.0, 1001.0, 1002.0]
    for record, (lat, lon) in zip(received, ARC_SECONDS, strict=True):
        assert math.isclose(record["lat"], lat / 3600.0)
        assert math.isclose(record["lon"], lon / 3600.0)
    assert reader.poll() == []  # each record is delivered once
    # the reader node's start_time: records stamped before it are skipped
    later = reader_http.StoreClient(positions.url)
    later_reader = reader_http.PollingReader(later, robot="rover_1", start=1001.0)
    assert [r["timestamp"] for r in later_reader.poll()] == [1001.0, 1002.0]


def test_follow_commands_last_until_the_next_velocity_change(bundle: Path, follow) -> None:
    http = client_module(bundle, "velocity_writer")
    client = http.StoreClient(follow.url, token=TOKEN)
    stamps = [50.0, 51.5, 52.0, 54.25]
    velocities = [(0.1, 0.0, 0.0), (0.2, 0.0, 0.5), (0.0, 0.0, -0.5), (0.3, 0.1, 0.0)]
    records = [
        http.to_record("ev3_a", t, dict(zip(("vx", "vy", "va"), v, strict=True)))
        for t, v in zip(stamps, velocities, strict=True)
    ]
    client.post(records[2:] + records[:2])  # arrival order differs from source order

    reader_http = client_module(bundle, "command_reader")
    reader = reader_http.PollingReader(reader_http.StoreClient(follow.url), robot="ev3_a")
    commands: list[dict] = []
    wait_for(lambda: commands.extend(reader.poll()) or len(commands) >= 3)
    assert [c["duration"] for c in commands] == [1.5, 0.5, 2.25]
    assert [(c["vx"], c["vy"], c["va"]) for c in commands] == velocities[:3]
    # the newest velocity waits for its successor, then gets its duration
    assert reader.poll() == []
    client.post([http.to_record("ev3_a", 55.0, {"vx": 0.0, "vy": 0.0, "va": 0.0})])
    wait_for(lambda: commands.extend(reader.poll()) or len(commands) >= 4)
    assert commands[3]["duration"] == 0.75 and commands[3]["timestamp"] == 54.25


def test_commands_of_two_robots_do_not_mix(follow) -> None:
    base = f"{follow.url}/FollowStore"
    body = {
        "records": [
            {"robot": "r_x", "timestamp": 10.0, "data": {"vx": 1.0, "vy": 0.0, "va": 0.0}},
            {"robot": "r_y", "timestamp": 10.5, "data": {"vx": 2.0, "vy": 0.0, "va": 0.0}},
            {"robot": "r_x", "timestamp": 13.0, "data": {"vx": 3.0, "vy": 0.0, "va": 0.0}},
            {"robot": "r_y", "timestamp": 11.0, "data": {"vx": 4.0, "vy": 0.0, "va": 0.0}},
        ]
    }
    assert request("POST", f"{base}/records/batch", body)[0] == 201

    def page():  # type: ignore[no-untyped-def]
        items = request("GET", f"{base}/Command?from=0&to=20")[2]["items"]
        return items if len(items) == 2 else None

    items = wait_for(page)
    assert {(c["robot"], c["duration"]) for c in items} == {("r_x", 3.0), ("r_y", 0.5)}


def test_rest_contract(positions) -> None:
    base = f"{positions.url}/PositionStore"
    record = {"robot": "rover_9", "timestamp": 5000.0, "data": {"lat": 36.0, "lon": 72}}
    status, headers, body = request("POST", f"{base}/records", record)
    assert status == 201
    assert headers["location"] == f"/PositionStore/records/{body['id']}"
    assert headers["etag"].startswith('"')

    status, headers, raw = request("GET", positions.url + headers["location"])
    assert status == 200 and raw["data"] == {"lat": 36.0, "lon": 72} and raw["robot"] == "rover_9"
    etag = headers["etag"]
    assert request("GET", f"{base}/records/{raw['id']}", headers={"If-None-Match": etag})[0] == 304
    status, head_headers, head_body = request("HEAD", f"{base}/records/{raw['id']}")
    assert status == 200 and head_headers["etag"] == etag and head_body is None

    status, headers, store = request("GET", base)
    assert status == 200 and store["raw"]["type"] == "PositionInSecond"
    assert headers["link"] == (
        '</PositionStore/records>; rel="related", '
        '</PositionStore/PositionInDEG>; rel="related", '
        '</PositionStore/errors>; rel="related", '
        '</PositionStore/subscriptions>; rel="related", '
        '</PositionStore/blueprint>; rel="related", '
        '</PositionStore/properties>; rel="related", '
        '</PositionStore/actions>; rel="related"'
    )
    assert 'rel="related"' in request("GET", positions.url + "/")[1]["link"]
    for path, allow in [
        ("", "GET, HEAD, OPTIONS"),
        ("/records", "GET, HEAD, POST, OPTIONS"),
        ("/PositionInDEG", "GET, HEAD, OPTIONS"),
        ("/PositionInDEG/1", "GET, HEAD, OPTIONS"),
    ]:
        status, headers, _ = request("OPTIONS", base + path)
        assert (status, headers["allow"]) == (204, allow)

    for method, path, allow in [
        ("DELETE", "/records/1", "GET, HEAD, OPTIONS"),
        ("PUT", "", "GET, HEAD, OPTIONS"),
        ("DELETE", "/records", "GET, HEAD, POST, OPTIONS"),
        ("POST", "/PositionInDEG", "GET, HEAD, OPTIONS"),
    ]:
        status, headers, body = request(method, base + path)
        assert (status, headers["allow"], body["detail"]) == (405, allow, "Method Not Allowed")

    refined = wait_for(lambda: request("GET", f"{base}/PositionInDEG?robot=rover_9")[2]["items"])
    assert refined[0]["lat"] == 0.01 and refined[0]["lon"] == 0.02
    status, _, one = request("GET", f"{base}/PositionInDEG/{refined[0]['id']}")
    assert status == 200 and one == refined[0]
    assert request("GET", f"{base}/PositionInDEG/999999")[0] == 404
    assert request("GET", f"{base}/Nothing")[0] == 404
    assert request("GET", f"{base}/PositionInDEG?limit=5000")[0] == 400
    openapi = request("GET", positions.url + "/openapi.json")[2]
    assert "/PositionStore/records/batch" in openapi["paths"]
    assert "/PositionStore/PositionInDEG" in openapi["paths"]


def test_pagination_follows_next_links(positions) -> None:
    base = f"{positions.url}/PositionStore"
    records = [
        {"robot": "pager", "timestamp": 7000.0 + i, "data": {"lat": 0.0, "lon": 0.0}}
        for i in range(7)
    ]
    assert request("POST", f"{base}/records/batch", {"records": records})[0] == 201
    url = f"{base}/records?robot=pager&limit=3&from=7000&to=7006"
    seen = []
    while url:
        _, headers, page = request("GET", url)
        seen += [r["timestamp"] for r in page["items"]]
        url = page["next"]
        assert ("link" in headers) == bool(url)
    assert seen == [7000.0 + i for i in range(6)]


BAD_RECORDS = [
    ({"robot": "r", "timestamp": 1.0, "data": {"lat": "north", "lon": 1.0}}, "data/lat"),
    ({"robot": "r", "timestamp": 1.0, "data": {"lat": 1.0}}, "data/lon"),
    ({"robot": "r", "timestamp": 1.0, "data": {"lat": 1.0, "lon": 1.0, "alt": 3}}, "data/alt"),
    ({"robot": "r", "timestamp": 1.0, "data": {"lat": True, "lon": 1.0}}, "data/lat"),
    ({"robot": "r; DROP TABLE", "timestamp": 1.0, "data": {"lat": 1.0, "lon": 1.0}}, "robot"),
    ({"robot": "r", "data": {"lat": 1.0, "lon": 1.0}}, "timestamp"),
]


@pytest.mark.parametrize(("record", "where"), BAD_RECORDS)
def test_bad_records_are_refused_with_the_reason(positions, record, where) -> None:
    base = f"{positions.url}/PositionStore"
    before = request("GET", f"{base}/records?limit=1000")[2]["items"]
    status, _, body = request("POST", f"{base}/records", record)
    assert status == 400
    assert any(reason["where"].endswith(where) for reason in body["detail"]), body
    assert request("GET", f"{base}/records?limit=1000")[2]["items"] == before


def test_batches_are_all_or_nothing_and_limited(positions) -> None:
    base = f"{positions.url}/PositionStore"
    good = {"robot": "batcher", "timestamp": 1.0, "data": {"lat": 1.0, "lon": 1.0}}
    bad = {"robot": "batcher", "timestamp": 2.0, "data": {"lat": None, "lon": 1.0}}
    status, _, body = request("POST", f"{base}/records/batch", {"records": [good, bad]})
    assert status == 400 and body["detail"][0]["where"] == "body/records/1/data/lat"
    status, _, body = request("POST", f"{base}/records/batch", {"records": [good] * 51})
    assert status == 400 and "at most 50" in body["detail"][0]["problem"]
    status, _, body = request("POST", f"{base}/records", raw=b"{not json")
    assert status == 400
    assert request("GET", f"{base}/records?robot=batcher")[2]["items"] == []


def test_writes_need_the_token(positions) -> None:
    base = f"{positions.url}/PositionStore"
    record = {"robot": "intruder", "timestamp": 1.0, "data": {"lat": 1.0, "lon": 1.0}}
    status, headers, body = request("POST", f"{base}/records", record, token=None)
    assert status == 401 and headers["www-authenticate"] == "Bearer"
    assert body["detail"] == "missing bearer token"
    status, _, body = request("POST", f"{base}/records/batch", {"records": [record]}, token="wrong")
    assert status == 401 and body["detail"] == "invalid bearer token"
    assert request("GET", f"{base}/records?robot=intruder")[2]["items"] == []


def test_writer_retries_until_the_service_answers(bundle: Path, positions) -> None:
    http = client_module(bundle, "position_writer")
    port_closed = http.StoreClient("http://127.0.0.1:9", token=TOKEN, timeout=0.5)
    writer = http.BatchingWriter(port_closed, robot="patient", linger=0.01)
    assert writer.submit(1.0, {"lat": 1.0, "lon": 2.0})
    assert not writer.flush(0.5)  # still retrying, the caller was never blocked
    writer.client.base = f"{positions.url}/PositionStore"  # the cloud comes back
    assert writer.flush(15)
    writer.close()
    assert request("GET", f"{positions.url}/PositionStore/records?robot=patient")[2]["items"]
    refused = http.BatchingWriter(http.StoreClient(positions.url, token="wrong"), robot="x")
    assert refused.submit(1.0, {"lat": 1.0, "lon": 2.0})
    assert refused.flush(10) and refused.rejected == 1 and refused.sent == 0
    refused.close()
    assert not writer.submit(1.0, {"lat": "nowhere"})  # not of the data type
