"""A feature model alone in a real editor: the documented Neovim set-up (docs/editors.md)
on a UVL file. Unsaved edits show what ``spl check FILE`` prints for the same text: a
constraint killing two features, their dead-feature warnings at their declarations; a
syntax error, its error alone (the warnings of the text before gone); the edits undone,
nothing. Like tests/live/test_lsp_neovim.py, it fails without Neovim, never skips."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from live.test_lsp_neovim import documented_snippet, neovim_version

MODEL = (
    "features\n\tCar\n\t\tmandatory\n\t\t\tEngine\n\t\toptional\n\t\t\tRadio\n"
    "\t\t\tNavigation\nconstraints\n\tNavigation => Radio\n"
)
KILLING, BROKEN = "\t!Radio", "\t!Radio &"

# Each edit unsaved, as a user types it: append the constraint, wait for both warnings;
# make it a syntax error, wait until only errors show; remove it, wait until none show.
PROBE = """
local out = {}
local function seen()
  local found = {}
  for _, d in ipairs(vim.diagnostic.get(0)) do
    local item = { severity = d.severity, message = d.message }
    item.line, item.col = d.lnum + 1, d.col + 1
    table.insert(found, item)
  end
  return found
end
local function all(severity, least)
  local shown = vim.diagnostic.get(0)
  for _, d in ipairs(shown) do
    if d.severity ~= severity then return false end
  end
  return #shown >= least
end
vim.api.nvim_buf_set_lines(0, -1, -1, false, { %(killing)s })
out.killed = vim.wait(%(wait)d, function() return all(vim.diagnostic.severity.WARN, 2) end, 50)
out.killed_diagnostics = seen()
vim.api.nvim_buf_set_lines(0, -2, -1, false, { %(broken)s })
out.broken = vim.wait(%(wait)d, function() return all(vim.diagnostic.severity.ERROR, 1) end, 50)
out.broken_diagnostics = seen()
vim.api.nvim_buf_set_lines(0, -2, -1, false, {})
out.cleared = vim.wait(%(wait)d, function() return #vim.diagnostic.get(0) == 0 end, 50)
vim.fn.writefile({ vim.fn.json_encode(out) }, %(result)s)
vim.cmd("qa!")
"""


def spl_check_of(text: str, path: Path) -> list[tuple[int, int, str, str]]:
    """What ``spl check FILE --json`` reports on ``path`` holding ``text``, sorted."""
    path.write_text(text, encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "spl", "check", "--json", str(path)],
        capture_output=True,
        text=True,
    )
    return sorted(
        (d["line"], d["col"], d["severity"], d["message"])
        for d in json.loads(done.stdout)["diagnostics"]
    )


def test_neovim_shows_the_analysis_of_an_unsaved_feature_model(tmp_path: Path) -> None:
    version = neovim_version()
    folder = tmp_path / "models"
    folder.mkdir()
    uvl = folder / "car.uvl"
    uvl.write_text(MODEL, encoding="utf-8")
    saved = tmp_path / "saved.uvl"
    killed = spl_check_of(MODEL + KILLING + "\n", saved)
    broken = spl_check_of(MODEL + BROKEN + "\n", saved)
    assert [d[2] for d in killed] == ["warning", "warning"]  # Radio, and Navigation with it
    assert broken and {d[2] for d in broken} == {"error"}
    assert spl_check_of(MODEL, saved) == []

    config = tmp_path / "config"
    config.mkdir()
    (config / "init.lua").write_text(documented_snippet(version))
    result = tmp_path / "result.json"
    probe = tmp_path / "probe.lua"
    probe.write_text(
        PROBE
        % {
            "killing": json.dumps(KILLING),
            "broken": json.dumps(BROKEN),
            "wait": 60_000,
            "result": json.dumps(str(result)),
        }
    )
    # the documented set-up runs `spl lsp` from the PATH: the spl of this test run
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    env.update(XDG_CONFIG_HOME=str(tmp_path / "xdg"), XDG_STATE_HOME=str(tmp_path / "state"))
    editor = ["nvim", "--headless", "-n", "-i", "NONE", "-u", str(config / "init.lua")]
    done = subprocess.run(
        [*editor, str(uvl), "-c", f"luafile {probe}"],
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
        timeout=240,
    )
    assert result.exists(), f"Neovim ended without a result: {done.stdout}{done.stderr}"
    seen = json.loads(result.read_text())
    severities = {1: "error", 2: "warning", 3: "info", 4: "hint"}

    def shown(key: str) -> list[tuple[int, int, str, str]]:
        found = seen[key] if isinstance(seen[key], list) else []  # Lua's {} reads as {}
        return sorted((d["line"], d["col"], severities[d["severity"]], d["message"]) for d in found)

    assert seen["killed"], "the dead features' warnings never reached Neovim"
    assert shown("killed_diagnostics") == killed
    assert seen["broken"], "the syntax error never replaced the warnings"
    assert shown("broken_diagnostics") == broken
    assert seen["cleared"], "undoing the edits did not clear the diagnostics"
    assert uvl.read_text(encoding="utf-8") == MODEL  # the editor never saved
