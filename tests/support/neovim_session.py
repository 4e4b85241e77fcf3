"""The documented Neovim set-up run headless on one file, for the tests of `spl lsp` in a
real editor (tests/live/test_lsp_neovim*.py).

Each test gives a Lua probe: what a user does in the editor, then the JSON it writes
to ``%(result)s``. The session starts Neovim with the ``init.lua`` lines docs/editors.md
gives for the installed version, ``spl lsp`` from the PATH being the spl of this test
run. Neovim is a Debian package (``apt-get install neovim``) that ``.ci/run`` installs;
without it these tests fail, never skip.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
WAIT_MS = 60_000  # how long a probe waits for the server (a loaded machine is slow)

# ``seen()``: the buffer's diagnostics, each with its severity, message, line and column
SEEN_LUA = """
local function seen()
  local found = {}
  for _, d in ipairs(vim.diagnostic.get(0)) do
    local item = { severity = d.severity, message = d.message }
    item.line, item.col = d.lnum + 1, d.col + 1
    table.insert(found, item)
  end
  return found
end
"""

SEVERITIES = {1: "error", 2: "warning", 3: "info", 4: "hint"}


def neovim_version() -> tuple[int, int]:
    nvim = shutil.which("nvim")
    assert nvim, "Neovim is not installed: apt-get install neovim (tests/support/neovim_session.py)"
    first = subprocess.run([nvim, "--version"], capture_output=True, text=True).stdout
    found = re.match(r"NVIM v(\d+)\.(\d+)", first)
    assert found, f"not a Neovim version: {first[:80]!r}"
    return int(found.group(1)), int(found.group(2))


def documented_snippet(version: tuple[int, int]) -> str:
    """The init.lua lines docs/editors.md gives for this Neovim version."""
    marker = "neovim-0.11" if version >= (0, 11) else "neovim-0.7"
    page = (ROOT / "docs" / "editors.md").read_text()
    block = re.search(rf"<!-- {marker} -->\n```lua\n(.*?)```", page, re.S)
    assert block, f"docs/editors.md has no <!-- {marker} --> block"
    return block.group(1)


def run_probe(tmp_path: Path, opened: Path, probe: str, **values: object) -> dict[str, Any]:
    """Neovim with the documented set-up on ``opened`` (started in its folder), running
    ``probe`` (``SEEN_LUA`` before it; ``values``, ``wait`` and ``result`` put in with
    ``%``); what the probe wrote."""
    config = tmp_path / "config"
    config.mkdir()
    (config / "init.lua").write_text(documented_snippet(neovim_version()))
    result = tmp_path / "result.json"
    script = tmp_path / "probe.lua"
    script.write_text(
        SEEN_LUA + probe % {**values, "wait": WAIT_MS, "result": json.dumps(str(result))}
    )
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    env.update(XDG_CONFIG_HOME=str(tmp_path / "xdg"), XDG_STATE_HOME=str(tmp_path / "state"))
    editor = ["nvim", "--headless", "-n", "-i", "NONE", "-u", str(config / "init.lua")]
    done = subprocess.run(
        [*editor, str(opened), "-c", f"luafile {script}"],
        cwd=opened.parent,
        env=env,
        capture_output=True,
        text=True,
        timeout=240,
    )
    assert result.exists(), f"Neovim ended without a result: {done.stdout}{done.stderr}"
    return json.loads(result.read_text())


def shown(found: object) -> list[tuple[int, int, str, str]]:
    """The diagnostics ``seen()`` gave, as (line, col, severity, message), in its order
    (an empty Lua table reads back as ``{}``, not a list)."""
    items = found if isinstance(found, list) else []
    return [(d["line"], d["col"], SEVERITIES[d["severity"]], d["message"]) for d in items]
