"""A service whose transform can fail: failing records are reported with the reason and
the others still refined; late records are reported; reads can require the token; the
service refuses to start without its token."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from spl.generators.service import generator as service
from spl.metamodels import tsm

from support.service_models import product
from support.service_runtime import TOKEN, RunningService, request, wait_for, write_files

T = tsm()


def one_store_system(system, store_name: str, transform):  # type: ignore[no-untyped-def]
    """``system`` with ``transform``'s two data types and a cloud holding one store of its
    input, refined by it every second."""
    system.dataTypes.extend([transform.input, transform.output])
    system.transforms.append(transform)
    cloud = T.CloudContainer(name="Cloud", endpoint=T.Endpoint())
    store = T.Store(name=store_name, raw=transform.input)
    store.refinements.append(T.Refinement(output=transform.output, transform=transform, period=1.0))
    cloud.stores.append(store)
    system.containers.append(cloud)
    return system


def ratio_system():  # type: ignore[no-untyped-def]
    system = T.System(name="Ratios")
    sample = T.DataType(name="Sample")
    ratio = T.DataType(name="Ratio")
    for name in ("a", "b"):
        sample.fields.append(T.Field(name=name, type=T.FieldType.double))
    for name in ("quotient", "growth"):
        ratio.fields.append(T.Field(name=name, type=T.FieldType.double))
    transform = T.Transform(name="Divide", input=sample, output=ratio)
    transform.assignments.append(
        T.Assignment(
            field="quotient",
            expression=T.BinaryExpression(
                operator="/", left=T.FieldReference(field="a"), right=T.FieldReference(field="b")
            ),
        )
    )
    transform.assignments.append(
        T.Assignment(
            field="growth",
            expression=T.BinaryExpression(
                operator="-",
                left=T.FieldReference(field="a"),
                right=T.FieldReference(record="prev", field="a"),
            ),
        )
    )
    return one_store_system(system, "RatioStore", transform)


@pytest.fixture(scope="module")
def directory(tmp_path_factory: pytest.TempPathFactory) -> Path:
    files = service.generate(product(name="ratios", system=ratio_system()))
    return write_files(files, tmp_path_factory.mktemp("ratios")) / "services" / "RatioStore"


def test_failing_records_are_reported_and_the_rest_refined(directory: Path) -> None:
    env = {
        "RATIO_STORE_TOKEN": TOKEN,
        "RATIO_STORE_TRANSFORM_PERIOD": "0.05",
        "RATIO_STORE_PROTECT_READS": "1",
    }
    running = RunningService(directory, "ratio_store_service", env).start()
    base = f"{running.url}/RatioStore"
    try:
        samples = [(1.0, 2.0, 4.0), (2.0, 0.0, 6.0), (3.0, 3.0, 9.0)]  # t, b, a
        records = [{"robot": "r", "timestamp": t, "data": {"a": a, "b": b}} for t, b, a in samples]
        assert request("POST", f"{base}/records/batch", {"records": records})[0] == 201
        items = wait_for(lambda: request("GET", f"{base}/Ratio")[2]["items"])
        errors = wait_for(lambda: request("GET", f"{base}/errors")[2]["items"])
        # the first record has no previous one, the second divides by zero
        assert sorted(e["message"] for e in errors) == [
            "Divide: division by zero",
            "Divide: no previous record of the same robot",
        ]
        assert [(i["timestamp"], i["quotient"], i["growth"]) for i in items] == [(3.0, 3.0, 3.0)]

        late = {"robot": "r", "timestamp": 0.5, "data": {"a": 1.0, "b": 1.0}}
        assert request("POST", f"{base}/records", late)[0] == 201
        wait_for(lambda: len(request("GET", f"{base}/errors")[2]["items"]) == 3)
        message = request("GET", f"{base}/errors")[2]["items"][2]["message"]
        assert message == "arrived after later records of its robot were transformed"

        status, _, body = request("GET", f"{base}/Ratio", token=None)
        assert (status, body["detail"]) == (401, "missing bearer token")
        assert request("GET", f"{base}/Ratio", token="wrong")[0] == 401
        assert request("GET", f"{running.url}/", token=None)[0] == 200  # health check
    finally:
        running.stop()


def test_the_service_does_not_start_without_its_token(directory: Path) -> None:
    result = subprocess.run(
        [
            sys.executable,
            "-c",
            # the application's own lifespan (runtime/service.py), as uvicorn enters it
            "import ratio_store_service.app as a, asyncio;"
            "asyncio.run(a.app.router.lifespan_context(a.app).__aenter__())",
        ],
        cwd=directory,
        capture_output=True,
        text=True,
        timeout=60,
        env={"PATH": "/usr/bin:/bin", "DATABASE_URL": "sqlite:///./never.db"},
    )
    assert result.returncode != 0
    assert "set RATIO_STORE_TOKEN to the bearer token writers must present" in result.stderr
    assert not (directory / "never.db").exists()


def tally_system():  # type: ignore[no-untyped-def]
    """Tally {n: int, tag: string} refined by Scale: n * 1000 (which can leave 64 bits)."""
    system = T.System(name="Tallies")
    tally, scaled = T.DataType(name="Tally"), T.DataType(name="Scaled")
    for data_type in (tally, scaled):
        data_type.fields.append(T.Field(name="n", type=T.FieldType.int))
        data_type.fields.append(T.Field(name="tag", type=T.FieldType.string))
    transform = T.Transform(name="Scale", input=tally, output=scaled)
    transform.assignments.append(
        T.Assignment(
            field="n",
            expression=T.BinaryExpression(
                operator="*", left=T.FieldReference(field="n"), right=T.NumberLiteral(value="1000")
            ),
        )
    )
    transform.assignments.append(
        T.Assignment(field="tag", expression=T.FieldReference(field="tag"))
    )
    return one_store_system(system, "TallyStore", transform)


def test_values_the_database_cannot_hold_never_jam_the_service(tmp_path: Path) -> None:
    """Reported on a line written from scratch: a refined value past 64 bits (n * 1000)
    made every later step fail ("Python int too large to convert to SQLite INTEGER"),
    so no record of any robot was refined again; ids and offsets past 64 bits were
    answered 500. Now such posts are 400, such a result is that record's error and
    the transformer goes on, and such ids are 404 / 400."""
    files = service.generate(product(name="tallies", system=tally_system()))
    directory = write_files(files, tmp_path) / "services" / "TallyStore"
    env = {"TALLY_STORE_TOKEN": TOKEN, "TALLY_STORE_TRANSFORM_PERIOD": "0.05"}
    running = RunningService(directory, "tally_store_service", env).start()
    base = f"{running.url}/TallyStore"
    try:

        def post(robot: str, t: float, n: int, tag: str = "x") -> int:
            record = {"robot": robot, "timestamp": t, "data": {"n": n, "tag": tag}}
            return request("POST", f"{base}/records", record)[0]

        assert post("bot_1", 0.5, 2**63) == 400  # no column holds it
        assert post("bot_1", 0.5, 1, tag="a\u0000b") == 400  # PostgreSQL text cannot
        assert post("bot_1", 1.0, 5) == 201
        assert post("bot_1", 2.0, 10**16) == 201  # fits; times 1000 it does not
        assert post("bot_1", 3.0, 7) == 201
        assert post("bot_2", 4.0, 8) == 201
        refined = wait_for(
            lambda: (
                len(request("GET", f"{base}/Scaled")[2]["items"]) == 3
                and request("GET", f"{base}/Scaled")[2]["items"]
            )
        )
        assert sorted((i["robot"], i["n"]) for i in refined) == [
            ("bot_1", 5000),
            ("bot_1", 7000),
            ("bot_2", 8000),
        ]
        errors = request("GET", f"{base}/errors")[2]["items"]
        assert [e["message"] for e in errors] == [
            "Scale: result is outside the 64-bit integer range"
        ]

        huge = "9" * 23
        assert request("GET", f"{base}/records/{huge}")[0] == 404
        assert request("GET", f"{base}/Scaled/{huge}")[0] == 404
        assert request("GET", f"{base}/records?after_id={huge}")[0] == 400
        assert request("GET", f"{base}/Scaled?offset={huge}")[0] == 400
    finally:
        running.stop()
