"""The README's two opening commands and the CI script stay what a new user runs.

The main command's ``spl`` invocation is run as written (bundle into a temporary
folder); ``.ci/run`` must run exactly the README's test command and then check and
validate every shipped product line.
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

from click.testing import CliRunner

from spl.cli import main

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def fenced_command(marker: str) -> str:
    match = re.search(rf"<!-- {marker} -->\n```sh\n(.+)\n```", README)
    assert match, f"README.md has no {marker} block"
    return match.group(1)


def test_main_command_resolves_the_paper_product(tmp_path: Path, monkeypatch) -> None:
    command = fenced_command("main-command")
    spl_part = command.split("&& .venv/bin/spl ", 1)[1]
    args = shlex.split(spl_part)
    assert args[0] == "resolve" and "-o" in args
    args[args.index("-o") + 1] = str(tmp_path / "bundle")
    monkeypatch.chdir(ROOT)
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert (tmp_path / "bundle" / "manifest.json").is_file()
    assert (tmp_path / "bundle" / "rapyuta" / "Robot.json").is_file()
    # what the README shows it print and write is what it prints and writes
    shown = re.search(r"\$ find (\S+) -type f \| sort\n(.*?)\n```", README, re.S)
    assert shown, "README.md shows no listing of the bundle"
    folder = shown.group(1)
    listed = [line.removeprefix(folder + "/") for line in shown.group(2).splitlines()]
    written = sorted(
        str(f.relative_to(tmp_path / "bundle"))
        for f in (tmp_path / "bundle").rglob("*")
        if f.is_file()
    )
    assert listed == written
    assert f"wrote {len(written)} files to {folder}" in README
    assert f"wrote {len(written)} files to" in result.output


def test_ci_script_runs_the_readme_test_command_then_validates_every_line() -> None:
    script = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    command = fenced_command("test-command")
    assert "pytest" in command
    assert "set -euo pipefail" in script.splitlines()
    # run as written, stopping the script when any part of the '&&' chain fails
    assert f"{command} || exit" in script.splitlines()
    assert re.search(r"spl check \"\$line\"", script)
    assert re.search(r"spl validate product_lines/\*/ --all .*--junit", script)


def test_ci_installs_what_spl_smoke_asks_for_and_smokes_every_listed_product() -> None:
    from spl.smoke.processes import ACTIONLIB_MISSING, ROS_MISSING

    script = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    (install,) = [line for line in script.splitlines() if "apt-get install" in line]
    packages = [
        *ROS_MISSING.split("apt-get install ", 1)[1].split(),
        *ACTIONLIB_MISSING.split("apt-get install ", 1)[1].split(),  # actions in spl smoke
    ]
    assert set(packages) | {"graphviz", "postgresql"} <= set(install.split())
    assert re.search(r"spl validate product_lines/\*/ --smoke .*--junit", script)
