"""`spl lsp` in a real editor: the documented Neovim set-up, run in a headless Neovim.

pytest-lsp drives the server the way the protocol says; this drives it the way an editor
does (its own document synchronisation, position encoding, filetype detection and
diagnostics store), from the ``init.lua`` lines docs/editors.md tells users to write, so
a snippet there that no longer works fails here (the session: tests/support/
neovim_session.py). Without Neovim this test fails, never skips.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from support.neovim_session import ROOT, run_probe, shown

BROKEN = "    require FruitDetektor"  # line 7 of orchard.rm reads "    require FruitDetector"
LINE = 7

# What the editor does, as a user would: break line 7 without saving, wait for the
# diagnostic, undo, wait for it to go, then ask where FruitDetector is declared.
PROBE = """
local out = { diagnostics = {} }
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
    line_dir = tmp_path / "orchard"
    shutil.copytree(ROOT / "product_lines" / "orchard", line_dir)
    original = (line_dir / "orchard.rm").read_text()
    lines = original.splitlines(keepends=True)
    assert lines[LINE - 1] == "    require FruitDetector\n"
    saved = tmp_path / "saved"
    shutil.copytree(line_dir, saved)
    expected = spl_check_of("".join([*lines[: LINE - 1], BROKEN + "\n", *lines[LINE:]]), saved)
    assert expected, "the planted error must be one spl check reports"

    seen = run_probe(
        tmp_path,
        line_dir / "orchard.rm",
        PROBE,
        index=LINE - 1,
        line=LINE,
        broken=json.dumps(BROKEN),
    )

    assert seen["shown"], "no diagnostic reached Neovim"
    assert shown(seen["diagnostics"]) == expected
    assert seen["cleared"], "undoing the edit did not clear the diagnostic"
    assert seen["definitions"] == [
        {"uri": (line_dir / "orchard.tsm").as_uri(), "line": declaration_line(line_dir)}
    ]
    assert (line_dir / "orchard.rm").read_text() == original  # the editor never saved


def declaration_line(line_dir: Path) -> int:
    text = (line_dir / "orchard.tsm").read_text().splitlines()
    return next(i for i, line in enumerate(text, 1) if "node FruitDetector " in line)
