"""``spl validate --jobs N`` when a worker process dies (the out-of-memory killer, a
crash in a native library, kill -9): its product runs again in a new worker and is
reported once, and a product whose workers keep ending is reported as an error. The run
never waits for a result that cannot come (docs/ci.md)."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import threading
from collections.abc import Iterator
from pathlib import Path

from support.smoke_runs import ROOT, run_spl, spl_command

LINES = [str(ROOT / "product_lines" / "mapping3d"), str(ROOT / "product_lines" / "orchard")]


def children(pid: int) -> list[int]:
    """The running child processes of ``pid``."""
    found = []
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit():
            continue
        try:
            stat = Path(f"/proc/{entry.name}/stat").read_bytes().rsplit(b")", 1)[1].split()
        except (OSError, IndexError):
            continue
        if int(stat[1]) == pid and stat[0] not in (b"Z", b"X"):
            found.append(int(entry.name))
    return found


def validate(*lines: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [*spl_command(), "validate", *lines, "--all", "--jobs", "2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=ROOT,
    )


@contextlib.contextmanager
def killed_after(run: subprocess.Popen[str], seconds: float = 120) -> Iterator[None]:
    """The run is killed if it has not ended within ``seconds``: a hang fails the test."""
    timer = threading.Timer(seconds, run.kill)
    timer.start()
    try:
        yield
    finally:
        timer.cancel()


def test_a_killed_worker_loses_no_product() -> None:
    by_one = run_spl(["validate", *LINES, "--all", "--jobs", "1"], timeout=300)
    assert by_one.returncode == 0, by_one.stdout + by_one.stderr
    run = validate(*LINES)
    assert run.stdout is not None
    with killed_after(run):
        # stdout is read through its buffer only: communicate() after readline() would
        # read the pipe past what readline() buffered
        first = run.stdout.readline() + run.stdout.readline()  # the workers are running
        workers = children(run.pid)
        assert workers, first
        os.kill(workers[0], signal.SIGKILL)
        rest = run.stdout.read()
        out, err = run.communicate()
    assert run.returncode == 0, first + rest + out + err
    assert first + rest + out == by_one.stdout  # every product, once, in the plan's order
    assert "Traceback" not in err


def test_a_product_whose_workers_keep_ending_is_an_error_not_a_hang() -> None:
    run = validate(LINES[0])
    stop = threading.Event()

    def kill_every_worker() -> None:
        while not stop.is_set():
            for pid in children(run.pid):
                with contextlib.suppress(ProcessLookupError):
                    os.kill(pid, signal.SIGKILL)
            stop.wait(0.005)

    killer = threading.Thread(target=kill_every_worker, daemon=True)
    killer.start()
    try:
        with killed_after(run):
            out, err = run.communicate()
    finally:
        stop.set()
        killer.join()
    assert run.returncode == 1, out + err
    verdicts = [v for v in out.splitlines() if v.startswith(("ok   ", "FAIL ", "ERROR "))]
    names = [v.split(" :: ")[1] for v in verdicts]
    assert len(names) == len(set(names)) == 17  # every product of the line, each once
    assert verdicts[0].startswith("ok   mapping3d :: ")  # the first runs in spl itself
    # each other product was lost, or finished before its worker was killed (a busy machine)
    lost = [v for v in verdicts if v.startswith("ERROR ")]
    assert len(lost) + sum(v.startswith("ok   ") for v in verdicts) == 17, out
    message = "lost: the worker process running it ended 3 times (last: killed by SIGKILL)"
    assert lost and out.count(message) == len(lost), out
    assert out.splitlines()[-1] == f"{17 - len(lost)} passed, {len(lost)} failed"
    assert "Traceback" not in err
