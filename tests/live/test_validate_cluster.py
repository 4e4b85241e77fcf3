"""``spl validate --scheduler``: the products on Dask distributed give the verdicts, the
JUnit report and the exit code of ``--jobs 1``, on a LocalCluster and on a scheduler and
workers started separately, also when a worker is killed in the middle of a ``--smoke``
run: its product runs again elsewhere, reported once (docs/ci.md)."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
import uuid
from pathlib import Path

from spl.resolver.resolution.product_line import load_product_line
from spl.smoke.processes import free_port

from support.smoke_runs import ROOT, leftovers, run_spl, spl_command, tagged_env

LINES = sorted(str(p) for p in (ROOT / "product_lines").iterdir() if (p / "products").is_dir())
SMOKED = [str(ROOT / "product_lines" / "mapping3d")]
SECONDS = re.compile(rb" in \d+(\.\d+)? s\b")  # a rehearsal's duration, in its summary


def test_a_local_cluster_gives_the_report_of_one_job(tmp_path: Path) -> None:
    one, cluster = tmp_path / "one.xml", tmp_path / "cluster.xml"
    by_one = run_spl(["validate", *LINES, "--all", "--junit", str(one)])
    on_cluster = run_spl(
        ["validate", *LINES, "--all", "--scheduler", "local:2", "--junit", str(cluster)]
    )
    assert (on_cluster.returncode, by_one.returncode) == (0, 0), on_cluster.stderr
    assert on_cluster.stdout == by_one.stdout
    assert cluster.read_bytes() == one.read_bytes()
    # every valid product of every line (what `spl products` lists, counted in this
    # process: five more spl processes took a fifth of the test), and each listed one
    # once more
    listed = sum(len(list(Path(line, "products").glob("*.yaml"))) for line in LINES)
    valid = sum(len(list(load_product_line(Path(line)).formula.products())) for line in LINES)
    assert f'tests="{valid + listed}"'.encode() in one.read_bytes()


def _dask(tag: str, *args: str) -> subprocess.Popen:
    module = "distributed.cli.dask_" + args[0]
    return subprocess.Popen(
        [sys.executable, "-m", module, *args[1:]],
        env=tagged_env(tag),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )


def test_a_killed_worker_loses_no_product_of_a_smoke_run(tmp_path: Path) -> None:
    # the scheduler and workers start while the run of --jobs 1 gives the reference
    tag, port = uuid.uuid4().hex, free_port()
    address = f"tcp://127.0.0.1:{port}"
    scheduler = _dask(
        tag, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"
    )
    workers = [
        _dask(tag, "worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard")
        for _ in range(2)
    ]
    report, reference = tmp_path / "cluster.xml", tmp_path / "one.xml"
    try:
        by_one = run_spl(["validate", *SMOKED, "--smoke", "--junit", str(reference)])
        assert by_one.returncode == 0, by_one.stdout + by_one.stderr
        options = ["--smoke", "--scheduler", address, "--junit", str(report)]
        # stdout is read through its buffer only: communicate() would read the pipe past
        # what readline() buffered, losing a verdict printed together with the first
        with (tmp_path / "stderr").open("w") as stderr:
            run = subprocess.Popen(
                [*spl_command(), "validate", *SMOKED, *options],
                env=tagged_env(tag),
                cwd=ROOT,
                stdout=subprocess.PIPE,
                stderr=stderr,
                text=True,
            )
        assert run.stdout is not None
        first = run.stdout.readline()  # one product done: both workers are on the next
        assert first.startswith("ok "), first
        os.killpg(workers[0].pid, signal.SIGKILL)
        timer = threading.Timer(300, run.kill)
        timer.start()
        rest = run.stdout.read()
        run.wait()
        timer.cancel()
        errors = (tmp_path / "stderr").read_text()
    finally:
        for process in (*workers, scheduler):
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGTERM)
                process.wait(timeout=30)
    assert run.returncode == 0, rest + errors
    assert (first + rest).splitlines()[-1] == by_one.stdout.splitlines()[-1]
    assert _verdicts(first + rest) == _verdicts(by_one.stdout)
    # the same report but for each rehearsal's duration
    assert SECONDS.sub(b"", report.read_bytes()) == SECONDS.sub(b"", reference.read_bytes())
    # the killed worker's rehearsal ended with it: nothing of the run is left running
    assert leftovers(tag, wait=15) == []


def _verdicts(output: str) -> list[str]:
    return [re.sub(r" in \d+(\.\d+)? s\b", "", line) for line in output.splitlines()]


def test_no_scheduler_is_a_clear_error() -> None:
    started = time.monotonic()
    port = free_port()
    result = run_spl(["validate", SMOKED[0], "--scheduler", f"tcp://127.0.0.1:{port}"])
    assert result.returncode == 2
    assert result.stderr.startswith(f"error: no Dask scheduler answers at tcp://127.0.0.1:{port}")
    assert "Traceback" not in result.stderr
    assert time.monotonic() - started < 60
