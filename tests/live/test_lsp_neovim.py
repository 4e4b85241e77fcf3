"""`spl lsp` in a real editor: the documented Neovim set-up, run in a headless Neovim.

pytest-lsp drives the server the way the protocol says; this drives it the way an editor
does (its own document synchronisation, position encoding, filetype detection and
diagnostics store), from the ``init.lua`` lines docs/editors.md tells users to write, so
a snippet there that no longer works fails here. Neovim is a Debian package (``apt-get
install neovim``) that ``.ci/run`` installs; without it this test fails, never skips.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BROKEN = "    require FruitDetektor"  # line 7 of orchard.rm reads "    require FruitDetector"
LINE = 7

# What the editor does, as a user would: break line 7 without saving, wait for the
# diagnostic, undo, wait for it to go, then ask where FruitDetector is declared.
PROBE = """
local out = { diagnostics = {} }
local function seen()
  local found = {}
  for _, d in ipairs(vim.diagnostic.get(0)) do
    local item = { severity = d.severity, message = d.message }
    item.line, item.col = d.lnum + 1, d.col + 1
    table.insert(found, item)
  end
  return found
end
local original = vim.api.nvim_buf_get_lines(0, %(index)d, %(index)d + 1, false)
vim.api.nvim_buf_set_lines(0, %(index)d, %(index)d + 1, false, { %(broken)s })
out.shown = vim.wait(%(wait)d, function() return #vim.diagnostic.get(0) > 0 end, 50)
out.diagnostics = seen()
vim.api.nvim_buf_set_lines(0, %(index)d, %(index)d + 1, false, original)
out.cleared = vim.wait(%(wait)d, function() return #vim.diagnostic.get(0) == 0 end, 50)
vim.api.nvim_win_set_cursor(0, { %(line)d, 14 })
local params = vim.lsp.util.make_position_params(0, "utf-16")
out.definitions = {}
local answers = vim.lsp.buf_request_sync(0, "textDocument/definition", params, %(wait)d)
for _, answer in pairs(answers or {}) do
  for _, loc in ipairs(answer.result or {}) do
    local range = loc.targetSelectionRange or loc.range
    table.insert(out.definitions, { uri = loc.targetUri or loc.uri, line = range.start.line + 1 })
  end
end
vim.fn.writefile({ vim.fn.json_encode(out) }, %(result)s)
vim.cmd("qa!")
"""


def neovim_version() -> tuple[int, int]:
    nvim = shutil.which("nvim")
    assert nvim, "Neovim is not installed: apt-get install neovim (tests/live/test_lsp_neovim.py)"
    first = subprocess.run([nvim, "--version"], capture_output=True, text=True).stdout
    major, minor = re.match(r"NVIM v(\d+)\.(\d+)", first).groups()
    return int(major), int(minor)


def documented_snippet(version: tuple[int, int]) -> str:
    """The init.lua lines docs/editors.md gives for this Neovim version."""
    marker = "neovim-0.11" if version >= (0, 11) else "neovim-0.7"
    page = (ROOT / "docs" / "editors.md").read_text()
    block = re.search(rf"<!-- {marker} -->\n```lua\n(.*?)```", page, re.S)
    assert block, f"docs/editors.md has no <!-- {marker} --> block"
    return block.group(1)


def spl_check_of(text: str, folder: Path) -> list[tuple[int, int, str, str]]:
    """What ``spl check --json`` reports on orchard.rm when it holds ``text``."""
    (folder / "orchard.rm").write_text(text)
    done = subprocess.run(
        [sys.executable, "-m", "spl", "check", "--json", str(folder)],
        capture_output=True,
        text=True,
    )
    return [
        (d["line"], d["col"], d["severity"], d["message"])
        for d in json.loads(done.stdout)["diagnostics"]
        if Path(d["file"]).name == "orchard.rm"
    ]


def test_documented_neovim_setup_shows_checks_and_definitions(tmp_path):
    version = neovim_version()
    line_dir = tmp_path / "orchard"
    shutil.copytree(ROOT / "product_lines" / "orchard", line_dir)
    original = (line_dir / "orchard.rm").read_text()
    lines = original.splitlines(keepends=True)
    assert lines[LINE - 1] == "    require FruitDetector\n"
    saved = tmp_path / "saved"
    shutil.copytree(line_dir, saved)
    expected = spl_check_of("".join([*lines[: LINE - 1], BROKEN + "\n", *lines[LINE:]]), saved)
    assert expected, "the planted error must be one spl check reports"

    config = tmp_path / "config"
    config.mkdir()
    (config / "init.lua").write_text(documented_snippet(version))
    result = tmp_path / "result.json"
    probe = tmp_path / "probe.lua"
    probe.write_text(
        PROBE
        % {
            "index": LINE - 1,
            "line": LINE,
            "broken": json.dumps(BROKEN),
            "wait": 60_000,
            "result": json.dumps(str(result)),
        }
    )
    # the documented set-up runs `spl lsp` from the PATH: the spl of this test run
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    env.update(XDG_CONFIG_HOME=str(tmp_path / "xdg"), XDG_STATE_HOME=str(tmp_path / "state"))
    done = subprocess.run(
        [
            "nvim",
            "--headless",
            "-n",
            "-i",
            "NONE",
            "-u",
            str(config / "init.lua"),
            str(line_dir / "orchard.rm"),
            "-c",
            f"luafile {probe}",
        ],
        cwd=line_dir,
        env=env,
        capture_output=True,
        text=True,
        timeout=240,
    )
    assert result.exists(), f"Neovim ended without a result: {done.stdout}{done.stderr}"
    seen = json.loads(result.read_text())

    assert seen["shown"], "no diagnostic reached Neovim"
    severities = {1: "error", 2: "warning", 3: "info", 4: "hint"}
    shown = [
        (d["line"], d["col"], severities[d["severity"]], d["message"]) for d in seen["diagnostics"]
    ]
    assert shown == expected
    assert seen["cleared"], "undoing the edit did not clear the diagnostic"
    assert seen["definitions"] == [
        {"uri": (line_dir / "orchard.tsm").as_uri(), "line": declaration_line(line_dir)}
    ]
    assert (line_dir / "orchard.rm").read_text() == original  # the editor never saved


def declaration_line(line_dir: Path) -> int:
    text = (line_dir / "orchard.tsm").read_text().splitlines()
    return next(i for i, line in enumerate(text, 1) if "node FruitDetector " in line)
