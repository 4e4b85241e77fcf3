"""A service whose transform can fail: failing records are reported with the reason and
the others still refined; late records are reported; reads can require the token; the
service refuses to start without its token."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from service_models import product
from service_runtime import TOKEN, RunningService, request, wait_for, write_files

from spl.generators import service
from spl.metamodels import tsm

T = tsm()


def ratio_system():  # type: ignore[no-untyped-def]
    system = T.System(name="Ratios")
    sample = T.DataType(name="Sample")
    ratio = T.DataType(name="Ratio")
    for name in ("a", "b"):
        sample.fields.append(T.Field(name=name, type=T.FieldType.double))
    for name in ("quotient", "growth"):
        ratio.fields.append(T.Field(name=name, type=T.FieldType.double))
    transform = T.Transform(name="Divide", input=sample, output=ratio)
    transform.assignments.append(T.Assignment(field="quotient", expression=T.BinaryExpression(
        operator="/", left=T.FieldReference(field="a"), right=T.FieldReference(field="b"))))
    transform.assignments.append(T.Assignment(field="growth", expression=T.BinaryExpression(
        operator="-", left=T.FieldReference(field="a"),
        right=T.FieldReference(record="prev", field="a"))))
    system.dataTypes.extend([sample, ratio])
    system.transforms.append(transform)
    cloud = T.CloudContainer(name="Cloud", endpoint=T.Endpoint())
    store = T.Store(name="RatioStore", raw=sample)
    store.refinements.append(T.Refinement(output=ratio, transform=transform, period=1.0))
    cloud.stores.append(store)
    system.containers.append(cloud)
    return system


@pytest.fixture(scope="module")
def directory(tmp_path_factory: pytest.TempPathFactory) -> Path:
    files = service.generate(product(name="ratios", system=ratio_system()))
    return write_files(files, tmp_path_factory.mktemp("ratios")) / "services" / "RatioStore"


def test_failing_records_are_reported_and_the_rest_refined(directory: Path) -> None:
    env = {"RATIO_STORE_TOKEN": TOKEN, "RATIO_STORE_TRANSFORM_PERIOD": "0.05",
           "RATIO_STORE_PROTECT_READS": "1"}
    running = RunningService(directory, "ratio_store_service", env).start()
    base = f"{running.url}/RatioStore"
    try:
        samples = [(1.0, 2.0, 4.0), (2.0, 0.0, 6.0), (3.0, 3.0, 9.0)]  # t, b, a
        records = [{"robot": "r", "timestamp": t, "data": {"a": a, "b": b}}
                   for t, b, a in samples]
        assert request("POST", f"{base}/records/batch", {"records": records})[0] == 201
        items = wait_for(lambda: request("GET", f"{base}/Ratio")[2]["items"])
        errors = wait_for(lambda: request("GET", f"{base}/errors")[2]["items"])
        # the first record has no previous one, the second divides by zero
        assert sorted(e["message"] for e in errors) == [
            "Divide: division by zero", "Divide: no previous record of the same robot"]
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
        [sys.executable, "-c", "import ratio_store_service.app as a, asyncio;"
         "asyncio.run(a.lifespan(a.app).__aenter__())"],
        cwd=directory, capture_output=True, text=True, timeout=60,
        env={"PATH": "/usr/bin:/bin", "DATABASE_URL": "sqlite:///./never.db"},
    )
    assert result.returncode != 0
    assert "set RATIO_STORE_TOKEN to the bearer token writers must present" in result.stderr
    assert not (directory / "never.db").exists()
