"""A feature model alone in a real editor: the documented Neovim set-up (docs/editors.md)
on a UVL file. Unsaved edits show what ``spl check FILE`` prints for the same text: a
constraint killing two features, their dead-feature warnings at their declarations; a
syntax error, its error alone (the warnings of the text before gone); the edits undone,
nothing. Like tests/live/test_lsp_neovim.py, it fails without Neovim, never skips."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from support.neovim_session import run_probe, shown

MODEL = (
    "features\n\tCar\n\t\tmandatory\n\t\t\tEngine\n\t\toptional\n\t\t\tRadio\n"
    "\t\t\tNavigation\nconstraints\n\tNavigation => Radio\n"
)
KILLING, BROKEN = "\t!Radio", "\t!Radio &"

# Each edit unsaved, as a user types it: append the constraint, wait for both warnings;
# make it a syntax error, wait until only errors show; remove it, wait until none show.
PROBE = """
local out = {}
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

    seen = run_probe(tmp_path, uvl, PROBE, killing=json.dumps(KILLING), broken=json.dumps(BROKEN))

    assert seen["killed"], "the dead features' warnings never reached Neovim"
    assert sorted(shown(seen["killed_diagnostics"])) == killed
    assert seen["broken"], "the syntax error never replaced the warnings"
    assert sorted(shown(seen["broken_diagnostics"])) == broken
    assert seen["cleared"], "undoing the edits did not clear the diagnostics"
    assert uvl.read_text(encoding="utf-8") == MODEL  # the editor never saved
