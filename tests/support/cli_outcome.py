"""The property every fuzz test checks on a run of the real command path: exit 0, or
exit 1 with at least one located ``file:line:col: error:`` line; never an internal
error or a traceback; and nothing written to the output folder when it fails."""

from __future__ import annotations

import re
from pathlib import Path

from click.testing import CliRunner, Result

from spl.cli import main

LOCATED_ERROR = re.compile(r"^\S.*:\d+:\d+: error: ", re.M)


def run(*args: str | Path) -> Result:
    """``spl ARGS`` in this process (click's runner), stdout and stderr kept apart."""
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=True)


def assert_clean_outcome(
    exit_code: int, stdout: str, stderr: str, about: str, out_parent: Path | None = None
) -> None:
    """``about`` says what ran on which input, so a failure shows the exact counterexample."""
    shown = f"{about}\n--- exit {exit_code}\n--- stdout\n{stdout}\n--- stderr\n{stderr}"
    assert "internal error" not in stderr, shown
    assert "Traceback" not in stdout + stderr, shown
    assert exit_code in (0, 1), shown
    if exit_code == 1:
        assert LOCATED_ERROR.search(stderr), shown
    if exit_code != 0 and out_parent is not None:
        assert not any(out_parent.iterdir()), shown


def assert_clean(result: Result, about: str, out_parent: Path | None = None) -> None:
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise AssertionError(about) from result.exception
    assert_clean_outcome(result.exit_code, result.stdout, result.stderr, about, out_parent)
