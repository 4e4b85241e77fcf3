"""``spl validate --scheduler``: an address it cannot use is a usage error (exit 2)
naming what to give, found before any worker starts or any scheduler is dialled. Two
were internal errors (``tcp://`` and ``tcp://host``: a ValueError from Dask), and
``local:99999`` began starting 99,999 worker processes."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LINE = ROOT / "product_lines" / "mapping3d"
MOST = 4 * (os.cpu_count() or 1)


@pytest.mark.parametrize(
    ("address", "says"),
    [
        ("local:0", f"local:N takes 1 to {MOST} workers (4 per CPU of this machine)"),
        (f"local:{MOST + 1}", f"local:N takes 1 to {MOST} workers"),
        ("local:" + "9" * 5000, f"local:N takes 1 to {MOST} workers"),
        ("local:two", f"local:N takes 1 to {MOST} workers"),
        ("tcp://", "give the scheduler's host and port, as tcp://HOST:PORT"),
        ("tcp://scheduler", "give the scheduler's host and port, as tcp://HOST:PORT"),
        ("tcp://scheduler:99999", "give the scheduler's host and port, as tcp://HOST:PORT"),
        ("tls://:8786", "give the scheduler's host and port, as tcp://HOST:PORT"),
        ("tcp://scheduler:8786/path", "give the scheduler's host and port, as tcp://HOST:PORT"),
        ("udp://scheduler:8786", "give tcp://HOST:PORT (a running scheduler) or local:N"),
    ],
)
def test_an_unusable_scheduler_address_is_a_usage_error(address: str, says: str) -> None:
    result = subprocess.run(
        [sys.executable, "-m", "spl", "validate", str(LINE), "--scheduler", address],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2, result.stderr
    assert result.stderr.startswith(f"error: --scheduler {address}: {says}")
    assert "internal error" not in result.stderr and "Traceback" not in result.stderr


@pytest.mark.parametrize("narrowing", [["--changed-from", str(LINE)], ["--since", "HEAD"]])
def test_a_narrowed_validation_with_a_scheduler_is_a_usage_error(narrowing: list[str]) -> None:
    result = subprocess.run(
        [sys.executable, "-m", "spl", "validate", str(LINE), "--scheduler", "local:1", *narrowing],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2, result.stderr
    assert "--changed-from and --since cannot be used with --scheduler" in result.stderr
    assert "use --jobs N" in result.stderr and "Traceback" not in result.stderr
