"""A generated data service reads its secrets from files, as a cluster mounts them
(docs/kubernetes.md, "Secrets as files"): the write token from the file
``<STORE>_TOKEN_FILE`` names and the database URL from ``DATABASE_URL_FILE``; the plain
variables still work for a local run, and a named file that cannot be read stops the
service at start with a message naming the variable and the file."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import TOKEN, RunningService, request, write_files

PACKAGE = "position_store_service"


@pytest.fixture(scope="module")
def directory(tmp_path_factory: pytest.TempPathFactory) -> Path:
    files = service.generate(product(features=("DataAcquisition", "Embedded", "Positions")))
    root = write_files(files, tmp_path_factory.mktemp("secrets"))
    return root / "services" / "PositionStore"


def stored_with(running: RunningService, token: str) -> int:
    record = {"robot": "r", "timestamp": 1.0, "data": {"lat": 1.0, "lon": 2.0}}
    base = f"{running.url}/PositionStore"
    return request("POST", f"{base}/records", record, token=token)[0]


@pytest.mark.parametrize("way", ["files", "variables"])
def test_the_service_takes_its_secrets_from_files_or_variables(directory, tmp_path, way):
    database = tmp_path / "store.db"
    url = f"sqlite:///{database}"
    if way == "files":
        (tmp_path / "token").write_text(TOKEN + "\n")  # as `echo` writes it
        (tmp_path / "database-url").write_text(url)
        env = {
            "POSITION_STORE_TOKEN_FILE": str(tmp_path / "token"),
            "DATABASE_URL_FILE": str(tmp_path / "database-url"),
            # a stale plain variable loses to the file
            "POSITION_STORE_TOKEN": "not-this-one",
        }
    else:
        env = {"POSITION_STORE_TOKEN": TOKEN, "DATABASE_URL": url}
    running = RunningService(directory, PACKAGE, env).start()
    try:
        assert stored_with(running, "not-this-one" if way == "files" else "wrong") == 401
        assert stored_with(running, TOKEN) == 201
    finally:
        running.stop()
    assert database.exists()  # the URL read (from the file, or the variable) was used


def test_an_unreadable_secret_file_stops_the_service_naming_it(directory, tmp_path):
    missing = tmp_path / "no-such-token"
    result = subprocess.run(
        [sys.executable, "-c", f"import {PACKAGE}.settings"],
        cwd=directory,
        capture_output=True,
        text=True,
        timeout=60,
        env={"PATH": "/usr/bin:/bin", "POSITION_STORE_TOKEN_FILE": str(missing)},
    )
    assert result.returncode != 0
    assert f"POSITION_STORE_TOKEN_FILE='{missing}': cannot read the secret" in result.stderr
    assert "Traceback" not in result.stderr
