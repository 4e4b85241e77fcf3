"""bench/readers.py times ``spl check`` with the fast readers switched off (docs/performance.md,
"Fast readers"): its prelude must find each language's reader where the tree keeps it
(``spl.dsl.<language>.reader``) and leave every text to textX, or the benchmark stops."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "bench" / "readers.py"
# the prelude, then: what reads a text of each language (the prelude's stand-in, a lambda
# leaving every text to textX, where the reader was switched off)
PROBE = "from spl.dsl.{0} import reader\nprint('{0}', reader.read.__name__, reader.read('x'))\n"


def _prelude() -> str:
    """``WITHOUT_READERS`` of the benchmark, read from its source (importing it would
    import the synthetic line's generator beside it)."""
    for statement in ast.parse(BENCH.read_text(encoding="utf-8")).body:
        if isinstance(statement, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "WITHOUT_READERS" for t in statement.targets
        ):
            return ast.literal_eval(statement.value)
    raise AssertionError("bench/readers.py has no WITHOUT_READERS")


def test_the_benchmark_switches_every_reader_off() -> None:
    prelude = _prelude().split("from spl.cli import main")[0]
    probes = "".join(PROBE.format(language) for language in ("tsm", "fm", "rm"))
    done = subprocess.run(
        [sys.executable, "-c", prelude + probes, "tsm,fm,rm"],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == [
        *("tsm", "<lambda>", "None"),
        *("fm", "<lambda>", "None"),
        *("rm", "<lambda>", "None"),
    ]


def test_a_spl_check_without_the_readers_checks_the_line() -> None:
    done = subprocess.run(
        [sys.executable, "-c", _prelude(), "tsm,fm,rm", "check", "product_lines/mapping3d"],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert done.returncode == 0, done.stderr
    assert "0 errors" in done.stdout + done.stderr
