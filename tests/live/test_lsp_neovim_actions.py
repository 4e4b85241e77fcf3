"""Actions in a real editor: the documented Neovim set-up (docs/editors.md) on the
navigation test line. Neovim shows the line's findings on the .tsm, goes from the
bridge's ``Cloud.Planner.move_base`` to the ``provides action`` statement, and completes
``calls action spare :`` with the line's action type only (docs/tsm.md, "Actions").
Like tests/live/test_lsp_neovim.py, it fails without Neovim, never skips."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from support.neovim_session import ROOT, run_probe

NAVIGATION = ROOT / "tests" / "models" / "navigation"

PROBE = """
local out = {}
out.shown = vim.wait(%(wait)d, function() return #vim.diagnostic.get(0) > 0 end, 50)
local function ask(method, line, col)
  vim.api.nvim_win_set_cursor(0, { line, col })
  local params = vim.lsp.util.make_position_params(0, "utf-16")
  return vim.lsp.buf_request_sync(0, method, params, %(wait)d) or {}
end
out.definitions = {}
for _, answer in pairs(ask("textDocument/definition", %(bridge_line)d, %(bridge_col)d)) do
  for _, loc in ipairs(answer.result or {}) do
    local range = loc.targetSelectionRange or loc.range
    table.insert(out.definitions, {
      uri = loc.targetUri or loc.uri, line = range.start.line + 1, col = range.start.character + 1,
    })
  end
end
vim.api.nvim_buf_set_lines(0, %(client_line)d, %(client_line)d, false, { %(typed)s })
out.labels = {}
for _, answer in pairs(ask("textDocument/completion", %(client_line)d + 1, %(typed_length)d)) do
  local result = answer.result or {}
  for _, item in ipairs(result.items or result) do table.insert(out.labels, item.label) end
end
vim.fn.writefile({ vim.fn.json_encode(out) }, %(result)s)
vim.cmd("qa!")
"""


def test_neovim_follows_and_completes_an_action(tmp_path: Path) -> None:
    line_dir = tmp_path / "navigation"
    shutil.copytree(NAVIGATION, line_dir)
    tsm = line_dir / "navigation.tsm"
    lines = tsm.read_text(encoding="utf-8").splitlines()
    bridge = next(i for i, t in enumerate(lines, 1) if t.startswith("bridge Robot.Behaviour"))
    server = next(i for i, t in enumerate(lines, 1) if "provides action move_base" in t)
    client = next(i for i, t in enumerate(lines, 1) if "calls action navigate" in t)
    typed = "        calls action spare : "

    seen = run_probe(
        tmp_path,
        tsm,
        PROBE,
        bridge_line=bridge,
        bridge_col=lines[bridge - 1].index("move_base") + 1,  # 0-based, inside it
        client_line=client,  # the new line goes after the client's
        typed=json.dumps(typed),
        typed_length=len(typed),
    )
    assert seen["shown"], "the line's findings never reached Neovim"
    column = lines[server - 1].index("move_base") + 1
    assert seen["definitions"] == [{"uri": tsm.as_uri(), "line": server, "col": column}]
    assert sorted(seen["labels"]) == ["move_base_msgs/MoveBase"]
