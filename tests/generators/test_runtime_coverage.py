"""Coverage of the runtimes where they run (docs/services.md, "The runtime package"):
under `coverage run` with the project's [tool.coverage], a process that a test starts
from a generated bundle is measured too, and its copy of a runtime module is reported
as spl's own file, so the live tests' runs of the services count in CI's report."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from spl.generators.clients import generator as clients
from spl.generators.service import generator as service

from support.service_models import product
from support.service_runtime import write_files

ROOT = Path(__file__).resolve().parents[2]
SERVICE_RUNTIME = ROOT / "src/spl/generators/service/runtime"
CLIENTS_RUNTIME = ROOT / "src/spl/generators/clients/runtime"

# started under coverage: a child process that imports one module of each runtime from
# the generated bundle and runs a function of each
CHILD = """
import sys
sys.path[:0] = sys.argv[1:3]
from position_store_service.runtime.turtle import string
from position_writer.runtime.writing import to_record
assert string("x") == '"x"'
assert to_record({"lat": "double"}, "r", 1, {"lat": 2}) == {
    "robot": "r", "timestamp": 1.0, "data": {"lat": 2.0}}
"""
PARENT = "import subprocess, sys\nsubprocess.run([sys.executable, *sys.argv[1:]], check=True)\n"


def test_a_process_started_from_a_bundle_counts_as_spls_runtime(tmp_path: Path) -> None:
    resolved = product()
    bundle = write_files({**service.generate(resolved), **clients.generate(resolved)}, tmp_path)
    services = bundle / "services/PositionStore"
    robots = bundle / "clients/ros1/position_writer/src"
    # only this run's measurement: not an outer `coverage run` of the test suite
    env = {k: v for k, v in os.environ.items() if not k.startswith("COVERAGE_")}
    data = tmp_path / ".coverage"
    coverage = [sys.executable, "-m", "coverage"]
    (tmp_path / "parent.py").write_text(PARENT)
    (tmp_path / "child.py").write_text(CHILD)
    subprocess.run(
        [*coverage, "run", f"--rcfile={ROOT / 'pyproject.toml'}", f"--data-file={data}",
         "parent.py", "child.py", str(services), str(robots)],
        cwd=tmp_path, env=env, check=True, capture_output=True,
    )  # fmt: skip
    subprocess.run(
        [*coverage, "combine", f"--rcfile={ROOT / 'pyproject.toml'}", f"--data-file={data}"],
        cwd=ROOT, env=env, check=True, capture_output=True,
    )  # fmt: skip
    report = tmp_path / "report.json"
    subprocess.run(
        [*coverage, "json", f"--rcfile={ROOT / 'pyproject.toml'}", f"--data-file={data}",
         "-o", str(report), "--fail-under=0"],
        cwd=ROOT, env=env, check=True, capture_output=True,
    )  # fmt: skip
    measured = json.loads(report.read_text())["files"]
    assert set(measured) >= {
        "src/spl/generators/service/runtime/turtle.py",
        "src/spl/generators/clients/runtime/writing.py",
    }
    assert not any("services/" in name or "clients/ros" in name for name in measured)
    turtle = measured["src/spl/generators/service/runtime/turtle.py"]
    assert turtle["summary"]["covered_lines"] > 0


def test_every_runtime_module_and_its_copies_are_measured_and_nothing_else() -> None:
    from coverage import Coverage
    from coverage.files import GlobMatcher

    config = Coverage(config_file=str(ROOT / "pyproject.toml")).config
    measured = GlobMatcher(config.run_include)
    resolved = product()
    bundle = {**service.generate(resolved), **clients.generate(resolved)}
    copies = [f"/tmp/b/{path}" for path in bundle if "/runtime/" in path]
    own = [str(p) for p in (*SERVICE_RUNTIME.glob("*.py"), *CLIENTS_RUNTIME.glob("*.py"))]
    assert copies and all(measured.match(path) for path in copies + own)
    assert not any(measured.match(f"/tmp/b/{p}") for p in bundle if "/runtime/" not in p)
    assert "subprocess" in config.patch and config.sigterm
