"""Busy processes beside a test, so that it runs as on a loaded machine (a CI runner
with parallel jobs, a robot's computer doing its own work): each one spins a core for
as long as the ``with`` block lasts, and is killed and reaped when it ends, whatever
happens in it."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def busy_processes(count: int = 3) -> Iterator[list[subprocess.Popen[bytes]]]:
    burners: list[subprocess.Popen[bytes]] = []
    try:
        for _ in range(count):
            burners.append(subprocess.Popen([sys.executable, "-c", "while True: pass"]))
        yield burners
    finally:
        for burner in burners:
            burner.kill()
        for burner in burners:
            burner.wait()
