"""The OpenAPI document of a generated service is its exact contract: unique operation
ids (FastAPI warned of duplicates), every answer the service can give documented per
operation, and ``schemathesis run`` of the service's own /openapi.json (all its phases
and checks, bounded examples, with the bearer token) finds nothing, with reads open and
with reads protected. Before, it found 22-24 undocumented answers (400, 204, 404, 304
where the document said 200 or 422)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import TOKEN, RunningService, request, write_files

PACKAGE = "position_store_service"
# The coverage phase sends every case the schema defines for each of the 46 operations
# (boundary and invalid values of every parameter and body; -n does not bound it);
# fuzzing sends up to 10 random cases per operation (CONFIGURATION: at 30, as the other
# phases, it took half of a run), and the stateful phase up to 30 scenarios along the
# API's links (-n). No --max-time: with one, fuzzing repeats until it is spent; --seed
# makes it reproducible.
CONFIGURATION = "[phases.fuzzing.generation]\nmax-examples = 10\n"
SCHEMATHESIS = [
    "-n",
    "30",
    "--seed",
    "7",
    "--generation-database",
    "none",
    "--no-color",
    "-c",
    "all",
    "--phases",
    "examples,coverage,fuzzing,stateful",
    "--request-timeout",
    "10",
]


@pytest.fixture(scope="module")
def directory(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = write_files(service.generate(product()), tmp_path_factory.mktemp("openapi"))
    return root / "services" / "PositionStore"


def _service(directory: Path, tmp_path: Path, **env: str) -> RunningService:
    environment = {
        "POSITION_STORE_TOKEN": TOKEN,
        "POSITION_STORE_TRANSFORM_PERIOD": "0.1",
        # callbacks to this machine are allowed (internal ones are refused otherwise)
        "POSITION_STORE_CALLBACK_HOSTS": "127.0.0.1",
        "DATABASE_URL": f"sqlite:///{tmp_path}/openapi.db",
        **env,
    }
    return RunningService(directory, PACKAGE, environment).start()


def test_operation_ids_are_unique_and_every_answer_is_documented(
    directory: Path, tmp_path: Path
) -> None:
    running = _service(directory, tmp_path)
    try:
        document = request("GET", f"{running.url}/openapi.json")[2]
    finally:
        running.stop()
    assert "Duplicate Operation ID" not in running.log.read_text()
    operations = {
        (path, method): operation
        for path, item in document["paths"].items()
        for method, operation in item.items()
    }
    ids = [operation["operationId"] for operation in operations.values()]
    assert len(ids) == len(set(ids))
    for (path, method), operation in operations.items():
        statuses = set(operation["responses"])
        assert "422" not in statuses, path  # the service answers 400 with the reasons
        if method == "options":
            assert (
                statuses <= {"204", "404"} and "Allow" in operation["responses"]["204"]["headers"]
            )
            continue
        assert "500" in statuses
        if method in ("get", "head"):
            assert {"200", "304", "406"} <= statuses, path
            content = operation["responses"]["200"]["content"]
            assert set(content) == {"text/turtle", "application/json"}, path
    records = operations[("/PositionStore/records", "get")]
    assert {"101", "201", "400", "401", "426"} <= set(records["responses"])
    assert [p["name"] for p in records["parameters"] if p["in"] == "header"] == [
        "upgrade",
        "callback",
    ]
    post = operations[("/PositionStore/records/batch", "post")]
    assert set(post["responses"]) == {"201", "400", "401", "406", "413", "500"}
    delete = operations[("/PositionStore/subscriptions/{subscription_id}", "delete")]
    assert set(delete["responses"]) == {"204", "400", "401", "404", "500"}


@pytest.mark.parametrize("protect_reads", ["0", "1"], ids=["open-reads", "protected-reads"])
def test_schemathesis_finds_nothing(directory: Path, tmp_path: Path, protect_reads: str) -> None:
    configuration = tmp_path / "schemathesis.toml"
    configuration.write_text(CONFIGURATION)
    running = _service(directory, tmp_path, POSITION_STORE_PROTECT_READS=protect_reads)
    try:
        run = subprocess.run(
            [
                sys.executable,
                "-m",
                "schemathesis.cli",
                "--config-file",
                str(configuration),
                "run",
                f"{running.url}/openapi.json",
                "-H",
                f"Authorization: Bearer {TOKEN}",
                *SCHEMATHESIS,
            ],
            capture_output=True,
            text=True,
            timeout=120,
            cwd=tmp_path,
        )
    finally:
        running.stop()
    report = run.stdout[-6000:] + run.stderr[-2000:]
    assert run.returncode == 0, report
    assert " passed" in run.stdout and "failure" not in run.stdout.split("SUMMARY")[-1], report
    log = running.log.read_text()
    assert "Traceback" not in log and "internal server error" not in log, log[-3000:]
