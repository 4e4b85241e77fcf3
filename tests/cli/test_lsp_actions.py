"""``spl lsp`` knows actions (docs/tsm.md, "Actions"; docs/editors.md), driven over stdio by
a real LSP client: go to definition and references lead from a client's ``-> NODE.SERVER``
and a bridge to the action server; completion offers the action types of the line after
``calls action X :``, after ``->`` (and in an .rm connect) only the nodes serving an action
and their action servers, and the two-word statements; hover says an action interface as
its statement; a client bound to a server of another kind is the diagnostic ``spl check``
gives."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import LanguageClient

from support.lsp_client import SERVER, change, close, diagnostics, open_file, position_of, start

ROOT = Path(__file__).resolve().parents[2]
NAVIGATION = ROOT / "tests" / "models" / "navigation"
MIGRATE = "    migrate Planner to Robot\n"
pytestmark = pytest.mark.asyncio(loop_scope="module")

TEXT = """\
system Nav

robot container Robot {
    topic Cmd : geometry_msgs/Twist name "/cmd_vel"

    node Behaviour {
        calls action navigate : move_base_msgs/MoveBase -> Planner.move_base
        calls clear : std_srvs/Empty -> Planner.clear_costmap
    }

    node Planner {
        provides action move_base : move_base_msgs/MoveBase name "/move_base"
        provides clear_costmap : std_srvs/Empty
        publishes cmd -> Cmd
    }

    node Dock {
        provides action dock : dock_msgs/Dock
    }
}

cloud container Cloud {
    node Mission {
        calls action go : move_base_msgs/MoveBase
    }
}

bridge Cloud.Mission.go -> Robot.Planner.move_base
"""
# where a new statement of Behaviour is typed
STATEMENT = "        calls clear : std_srvs/Empty -> Planner.clear_costmap\n"


@pytest_lsp.fixture(config=SERVER, scope="module")
async def client(lsp_client: LanguageClient, tmp_path_factory):
    await start(lsp_client, tmp_path_factory.getbasetemp())
    yield
    await lsp_client.shutdown_session()


@pytest.fixture
def nav(tmp_path: Path) -> Path:
    path = tmp_path / "nav.tsm"
    path.write_text(TEXT, encoding="utf-8")
    return path


def document(path: Path) -> types.TextDocumentIdentifier:
    return types.TextDocumentIdentifier(path.resolve().as_uri())


async def test_definition_and_references_lead_to_the_action_server(
    client: LanguageClient, nav: Path
):
    open_file(client, nav)
    await diagnostics(client, nav, lambda d: d == [])
    server = position_of(TEXT, "provides action move_base", shift=16)
    for needle, shift in [("-> Planner.move_base", 11), ("Robot.Planner.move_base", 14)]:
        (location,) = await client.text_document_definition_async(
            types.DefinitionParams(document(nav), position_of(TEXT, needle, shift=shift))
        )
        assert location.uri == nav.resolve().as_uri(), needle
        assert location.range.start == server, needle
    found = await client.text_document_references_async(
        types.ReferenceParams(
            context=types.ReferenceContext(include_declaration=True),
            text_document=document(nav),
            position=server,
        )
    )
    assert sorted((r.range.start.line, r.range.start.character) for r in found) == sorted(
        (p.line, p.character)
        for p in (
            server,
            position_of(TEXT, "-> Planner.move_base", shift=11),
            position_of(TEXT, "Robot.Planner.move_base", shift=14),
        )
    )
    close(client, nav)


async def test_completion_offers_what_an_action_statement_may_name(
    client: LanguageClient, nav: Path
):
    open_file(client, nav)
    await diagnostics(client, nav, lambda d: d == [])
    versions = iter(range(2, 100))

    async def completed(typed: str) -> list[types.CompletionItem]:
        """The items offered at the end of ``typed``, a new line of node Behaviour."""
        line = STATEMENT + f"        {typed}"
        edited = TEXT.replace(STATEMENT, line + "\n")
        change(client, nav, edited, next(versions))
        result = await client.text_document_completion_async(
            types.CompletionParams(document(nav), position_of(edited, line, shift=len(line)))
        )
        return result.items

    async def labels(typed: str) -> set[str]:
        return {item.label for item in await completed(typed)}

    # the action types of the line, not the services' or the topics'
    assert await labels("calls action spare : ") == {"move_base_msgs/MoveBase", "dock_msgs/Dock"}
    assert await labels("calls spare : ") == {"std_srvs/Empty"}
    typing = await completed("calls action spare : move_base_msgs/Mo")
    assert typing
    for item in typing:
        edited_range = item.text_edit.range  # the whole type typed so far is replaced
        assert edited_range.start.character == len("        calls action spare : ")
        assert edited_range.end.character == len("        calls action spare : move_base_msgs/Mo")
    # after ->, the nodes of the container that serve an action, then their action servers
    assert await labels("calls action spare -> ") == {"Planner", "Dock"}
    assert await labels("calls action spare -> Planner.") == {"move_base"}
    assert await labels("calls spare -> Planner.") == {"clear_costmap"}
    # the two-word statements, and after the first word the word that may follow it
    assert {"provides action", "calls action", "provides", "calls"} <= await labels("")
    assert "action" not in await labels("")
    assert await labels("calls ") == {"action"}
    assert await labels("provides ") == {"action"}
    close(client, nav)


async def test_a_bridge_from_an_action_client_is_offered_action_servers(
    client: LanguageClient, nav: Path
):
    open_file(client, nav)
    await diagnostics(client, nav, lambda d: d == [])
    edited = TEXT + "bridge Cloud.Mission.go -> Robot.Planner.\n"
    change(client, nav, edited, 2)
    result = await client.text_document_completion_async(
        types.CompletionParams(
            document(nav), position_of(edited, "Robot.Planner.\n", shift=len("Robot.Planner."))
        )
    )
    assert {item.label for item in result.items} == {"move_base"}
    close(client, nav)


async def test_hover_says_an_action_interface_as_its_statement(client: LanguageClient, nav: Path):
    open_file(client, nav)
    await diagnostics(client, nav, lambda d: d == [])

    async def hover(needle: str, shift: int) -> str:
        result = await client.text_document_hover_async(
            types.HoverParams(document(nav), position_of(TEXT, needle, shift=shift))
        )
        return result.contents.value

    client_text = await hover("calls action navigate", 14)
    assert "calls action `navigate` : `move_base_msgs/MoveBase` -> `Planner.move_base`" in (
        client_text
    )
    assert "action client of node `Behaviour`" in client_text
    server_text = await hover("-> Planner.move_base", 11)
    assert "provides action `move_base` : `move_base_msgs/MoveBase`" in server_text
    assert "action server of node `Planner`" in server_text
    node_text = await hover("-> Planner.move_base", 5)
    assert "- provides action `move_base` : `move_base_msgs/MoveBase`" in node_text
    close(client, nav)


def spl_check(path: Path) -> list[dict]:
    done = subprocess.run(
        [sys.executable, "-m", "spl", "check", "--json", str(path)],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    return json.loads(done.stdout)["diagnostics"]


async def test_a_client_bound_to_a_service_is_spl_checks_diagnostic(
    client: LanguageClient, nav: Path
):
    broken = TEXT.replace("-> Planner.move_base\n", "-> Planner.clear_costmap\n")
    open_file(client, nav, broken)
    (found,) = await diagnostics(client, nav, lambda d: len(d) > 0)
    nav.write_text(broken, encoding="utf-8")
    (checked,) = spl_check(nav)
    assert found.message == checked["message"]
    assert found.message.startswith("kind mismatch: Robot.Behaviour.navigate (")
    assert "is an action client, Robot.Planner.clear_costmap (" in found.message
    assert found.message.endswith("is a service server, not an action server")
    assert found.range.start == position_of(broken, "-> Planner.clear_costmap", shift=11)
    assert (found.range.start.line + 1, found.range.start.character + 1) == (
        checked["line"],
        checked["col"],
    )
    change(client, nav, TEXT, 2)
    await diagnostics(client, nav, lambda d: d == [])
    close(client, nav)


async def test_an_rm_connect_of_an_action_client_is_offered_action_servers(
    client: LanguageClient, tmp_path: Path
):
    line = tmp_path / "navigation"
    shutil.copytree(NAVIGATION, line)
    rm = line / "navigation.rm"
    text = rm.read_text(encoding="utf-8")
    open_file(client, rm)
    await diagnostics(client, rm, lambda d: d == [])
    versions = iter(range(2, 100))

    async def labels(typed: str) -> set[str]:
        edited = text.replace(MIGRATE, MIGRATE + f"    {typed}\n")
        change(client, rm, edited, next(versions))
        result = await client.text_document_completion_async(
            types.CompletionParams(document(rm), position_of(edited, typed, shift=len(typed)))
        )
        return {item.label for item in result.items}

    # of the line's four nodes, the one serving an action, then its action server only
    assert await labels("connect Behaviour.navigate to server ") == {"Planner"}
    assert await labels("connect Behaviour.navigate to server Planner.") == {"move_base"}
    assert await labels("connect bridge Behaviour.navigate -> Planner.") == {"move_base"}
    # a topic's interface is not a client: every node, every member
    assert {"scan", "cmd_vel", "move_base"} <= await labels("connect Lidar.scan to server Planner.")
    close(client, rm)
