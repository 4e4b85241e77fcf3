"""``spl lsp`` driven over stdio by a real LSP client: diagnostics from unsaved text
(the very findings of ``spl check``), go to definition, references, completion,
hover, outline, formatting, robustness and a clean shutdown."""

from __future__ import annotations

import asyncio
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pygls.lsp.client import LanguageClient as BaseLanguageClient
from pytest_lsp import LanguageClient

from support.lsp_client import (
    SERVER,
    change,
    close,
    diagnostics,
    open_file,
    position_of,
    start,
    uri,
)

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest_lsp.fixture(config=SERVER, scope="module")
async def client(lsp_client: LanguageClient, tmp_path_factory):
    await start(lsp_client, tmp_path_factory.getbasetemp())
    yield
    await lsp_client.shutdown_session()


@pytest.fixture
def orchard(tmp_path: Path) -> Path:
    """A copy of the orchard product line the test may edit."""
    target = tmp_path / "orchard"
    shutil.copytree(ROOT / "product_lines" / "orchard", target)
    return target


def spl_check(target: Path) -> list[dict]:
    """The diagnostics ``spl check --json`` reports for a saved file or folder."""
    done = subprocess.run(
        [sys.executable, "-m", "spl", "check", "--json", str(target)],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    return json.loads(done.stdout)["diagnostics"]


def as_spl(diagnostic: types.Diagnostic, text: str) -> tuple:
    """An editor diagnostic as spl prints it: 1-based line and character column."""
    line = diagnostic.range.start.line
    prefix = text.split("\n")[line].encode("utf-16-le")[: 2 * diagnostic.range.start.character]
    severity = {1: "error", 2: "warning", 3: "info"}[diagnostic.severity]
    return (
        line + 1,
        len(prefix.decode("utf-16-le")) + 1,
        severity,
        diagnostic.code,
        diagnostic.message,
    )


def expected(found: list[dict], path: Path) -> list[tuple]:
    return [
        (d["line"], d["col"], d["severity"], d["code"], d["message"])
        for d in found
        if Path(d["file"]).resolve() == path.resolve()
    ]


async def test_initialize_announces_every_feature(client: LanguageClient):
    capabilities = client.initialize_result.capabilities
    assert capabilities.definition_provider
    assert capabilities.references_provider
    assert capabilities.hover_provider
    assert capabilities.document_symbol_provider
    assert capabilities.document_formatting_provider
    assert list(capabilities.completion_provider.trigger_characters) == ["."]


async def test_broken_rm_shows_spl_checks_error_then_clears_when_fixed(
    client: LanguageClient, orchard: Path
):
    rm = orchard / "orchard.rm"
    good = rm.read_text(encoding="utf-8")
    broken = good.replace("    require YieldMapper\n", "    require YieldMaper\n")
    open_file(client, rm, broken)
    found = await diagnostics(client, rm, lambda d: len(d) > 0)
    rm.write_text(broken, encoding="utf-8")  # what `spl check` reports on the saved file
    assert [as_spl(d, broken) for d in found] == expected(spl_check(orchard), rm)
    (diagnostic,) = found
    assert diagnostic.range.start == position_of(broken, "require YieldMaper")
    assert diagnostic.message == "unknown node or store YieldMaper"
    change(client, rm, good, 2)
    await diagnostics(client, rm, lambda d: d == [])
    close(client, rm)


async def test_column_counts_utf16_units_after_a_non_ascii_character(
    client: LanguageClient, tmp_path: Path
):
    tsm = tmp_path / "robots.tsm"
    text = (
        "system Robots\n"
        "robot container Robot {\n"
        '    /* 🤖 café */ topic Cmd : geometry_msgs/Twist name "/cmd vel"\n'
        "}\n"
    )
    open_file(client, tsm, text)
    (diagnostic,) = await diagnostics(client, tsm, lambda d: len(d) > 0)
    tsm.write_text(text, encoding="utf-8")
    (spl,) = expected(spl_check(tsm), tsm)
    assert as_spl(diagnostic, text) == spl
    # 🤖 is one character for spl and two UTF-16 units for the editor
    assert diagnostic.range.start.line == 2
    assert diagnostic.range.start.character == spl[1] - 1 + 1
    close(client, tsm)


async def test_rm_is_checked_against_the_unsaved_tsm(client: LanguageClient, orchard: Path):
    rm, tsm = orchard / "orchard.rm", orchard / "orchard.tsm"
    open_file(client, rm)
    await diagnostics(client, rm, lambda d: d == [])
    tsm_text = tsm.read_text(encoding="utf-8")
    renamed = tsm_text.replace("node YieldMapper {", "node YieldMap {")
    open_file(client, tsm, renamed)
    found = await diagnostics(client, rm, lambda d: len(d) > 0)
    assert {d.message for d in found} >= {"unknown node or store YieldMapper"}
    change(client, tsm, tsm_text, 2)
    await diagnostics(client, rm, lambda d: d == [])
    close(client, rm, tsm)


async def test_product_line_findings_appear_on_the_element(client: LanguageClient, orchard: Path):
    rm = orchard / "orchard.rm"
    text = rm.read_text(encoding="utf-8") + (
        "\nwhen VacuumGripper selected {\n    implementation Gripper = orchard_arm/other\n}\n"
    )
    open_file(client, rm, text)
    found = await diagnostics(client, rm, lambda d: any(x.code == "SPL012" for x in d))
    rm.write_text(text, encoding="utf-8")
    # spl check's error (exit 1) is a warning on the element in the editor
    checked = expected(spl_check(orchard), rm)
    assert {d[2] for d in checked if d[3] == "SPL012"} == {"error"}
    assert [as_spl(d, text) for d in found] == [
        (*d[:2], "warning" if d[3] == "SPL012" else d[2], *d[3:]) for d in checked
    ]
    close(client, rm)


async def test_go_to_definition_from_rm_into_tsm_and_fm(client: LanguageClient, orchard: Path):
    rm = orchard / "orchard.rm"
    text = rm.read_text(encoding="utf-8")
    open_file(client, rm)
    await diagnostics(client, rm, lambda d: d == [])
    tsm_text = (orchard / "orchard.tsm").read_text(encoding="utf-8")
    cases = [
        ("migrate OrchardCloud.FruitDetector", 22, "orchard.tsm", "node FruitDetector", 5),
        (
            "migrate OrchardCloud.FruitDetector to Harvester",
            40,
            "orchard.tsm",
            "container Harvester",
            10,
        ),
        (
            "connect FruitDetector.image to topic Harvester.Image",
            48,
            "orchard.tsm",
            "topic Image",
            6,
        ),
        ("when OnboardDetection", 6, "orchard.fm", "OnboardDetection {", 0),
        ("feature Scouting.altitude", 18, "orchard.fm", "attribute altitude", 10),
        ("Scout.Mission.next_row ->", 15, "orchard.tsm", "calls      next_row", 11),
    ]
    for needle, shift, file, target, target_shift in cases:
        result = await client.text_document_definition_async(
            types.DefinitionParams(
                text_document=types.TextDocumentIdentifier(uri(rm)),
                position=position_of(text, needle, shift=shift),
            )
        )
        target_text = (orchard / file).read_text(encoding="utf-8")
        (location,) = result
        assert location.uri == uri(orchard / file), needle
        assert location.range.start == position_of(target_text, target, shift=target_shift), needle
    # inside one file: the topic an interface names, the server `calls` names
    open_file(client, orchard / "orchard.tsm")
    for needle, shift, target, target_shift in [
        ("publishes image -> Image", 19, "topic Image", 6),
        ("calls      grasp   -> Gripper.grasp", 33, "provides grasp", 9),
        ("bridge Harvester.Navigator.plan", 30, "calls      plan", 11),
    ]:
        (location,) = await client.text_document_definition_async(
            types.DefinitionParams(
                text_document=types.TextDocumentIdentifier(uri(orchard / "orchard.tsm")),
                position=position_of(tsm_text, needle, shift=shift),
            )
        )
        assert location.range.start == position_of(tsm_text, target, shift=target_shift), needle
    close(client, rm, orchard / "orchard.tsm")


async def test_references_of_a_node_and_a_feature_across_files(
    client: LanguageClient, orchard: Path
):
    rm = orchard / "orchard.rm"
    text = rm.read_text(encoding="utf-8")
    open_file(client, rm)
    await diagnostics(client, rm, lambda d: d == [])
    found = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=types.TextDocumentIdentifier(uri(rm)),
            position=position_of(text, "require FruitDetector", shift=10),
            context=types.ReferenceContext(include_declaration=True),
        )
    )
    places = sorted((Path(types_uri(x.uri)).name, x.range.start.line) for x in found)
    expected_rm = sorted(
        ("orchard.rm", n) for n, line in enumerate(text.split("\n")) if "FruitDetector" in line
    )
    assert [p for p in places if p[0] == "orchard.rm"] == expected_rm
    tsm_lines = (orchard / "orchard.tsm").read_text(encoding="utf-8").split("\n")
    declared = next(n for n, line in enumerate(tsm_lines) if "node FruitDetector" in line)
    assert [p for p in places if p[0] == "orchard.tsm"] == [("orchard.tsm", declared)]
    found = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=types.TextDocumentIdentifier(uri(rm)),
            position=position_of(text, "when Scouting", shift=6),
            context=types.ReferenceContext(include_declaration=False),
        )
    )
    files = sorted(Path(types_uri(x.uri)).name for x in found)
    assert files == ["orchard.fm", "orchard.rm", "orchard.rm"]  # the constraint; when, feature
    close(client, rm)


def types_uri(value: str) -> str:
    return value.removeprefix("file://")


async def test_completion_offers_names_where_names_are_expected(
    client: LanguageClient, orchard: Path
):
    rm = orchard / "orchard.rm"
    text = rm.read_text(encoding="utf-8")
    open_file(client, rm)
    await diagnostics(client, rm, lambda d: d == [])

    versions = iter(range(2, 100))

    async def labels(edited: str, needle: str) -> set[str]:
        change(client, rm, edited, next(versions))
        result = await client.text_document_completion_async(
            types.CompletionParams(
                text_document=types.TextDocumentIdentifier(uri(rm)),
                position=position_of(
                    edited, needle, occurrence=edited.count(needle) - 1, shift=len(needle)
                ),
            )
        )
        return {item.label for item in result.items}

    base = text + "\nwhen Scouting selected {\n    "
    nodes = await labels(base + "require \n}\n", "    require ")
    assert {"Navigator", "FruitDetector", "PathPlanner", "RowScheduler"} <= nodes
    assert "Camera" in nodes  # declared in two containers: offered, to be qualified
    assert await labels(base + "migrate Navigator to \n}\n", "migrate Navigator to ") == {
        "Harvester",
        "Scout",
        "OrchardCloud",
    }
    assert {"image", "detections", "threshold", "model"} <= await labels(
        base + "connect FruitDetector.\n}\n", "connect FruitDetector."
    )
    topics = await labels(base + "connect Navigator.plan to topic \n}\n", "to topic ")
    assert {"Image", "Odom", "CmdVel", "Fruits"} <= topics, topics
    features = await labels(text + "\nwhen \n", "\nwhen ")
    assert {"Scouting", "YieldMapping", "SoftGripper"} <= features
    keywords = await labels(base + "\n}\n", "selected {\n    ")
    assert {"require", "connect", "migrate", "parameter", "implementation"} <= keywords
    close(client, rm)


async def test_hover_describes_features_nodes_and_topics(client: LanguageClient, orchard: Path):
    rm = orchard / "orchard.rm"
    text = rm.read_text(encoding="utf-8")
    open_file(client, rm)
    await diagnostics(client, rm, lambda d: d == [])

    async def hover(needle: str, shift: int) -> str:
        result = await client.text_document_hover_async(
            types.HoverParams(
                text_document=types.TextDocumentIdentifier(uri(rm)),
                position=position_of(text, needle, shift=shift),
            )
        )
        return result.contents.value

    feature = await hover("when YieldMapping selected", 6)
    assert "optional, child of `Harvesting`" in feature
    assert "sharing `protected`" in feature
    assert "attribute `resolution : double = 0.5`" in feature
    assert "constraint `YieldMapping requires Scouting`" in feature
    node = await hover("require FruitDetector", 10)
    assert "in cloud container `OrchardCloud`" in node
    assert "implementation `" in node and "publishes `detections`" in node
    # each interface as its .tsm statement says it: keyword, type, and what it is bound to
    assert "- subscribes `image` : `sensor_msgs/Image` <- topic `HarvesterImage`" in node
    assert "- publishes `detections` : `vision_msgs/Detection2DArray` -> topic `Fruits`" in node
    arm = await hover("connect ArmController", 10)
    assert "- calls `grasp` : `std_srvs/Trigger` -> `Gripper.grasp`" in arm
    planner = await hover("OrchardCloud.PathPlanner.plan", 15)
    assert "- provides `plan` : `nav_msgs/GetPlan`\n" in planner
    topic = await hover("topic Harvester.Image", 17)
    assert "type `sensor_msgs/Image`" in topic and "ROS name `/camera/image_raw`" in topic
    close(client, rm)


async def test_outline_of_the_three_languages(client: LanguageClient, orchard: Path):
    names = {}
    for file in ("orchard.tsm", "orchard.fm", "orchard.rm"):
        path = orchard / file
        open_file(client, path)
        await diagnostics(client, path, lambda d: d == [])
        for _ in range(100):  # the model is stored right after the diagnostics are sent
            symbols = await client.text_document_document_symbol_async(
                types.DocumentSymbolParams(text_document=types.TextDocumentIdentifier(uri(path)))
            )
            if symbols:
                break
        names[file] = symbols
    assert [s.name for s in names["orchard.tsm"]] == ["Harvester", "Scout", "OrchardCloud"]
    harvester = names["orchard.tsm"][0]
    assert "Camera" in [c.name for c in harvester.children]
    (root,) = names["orchard.fm"]
    assert root.name == "Harvesting"
    assert [c.name for c in root.children][:2] == ["Detection", "Planning"]
    assert names["orchard.rm"][0].name == "when CloudDetection selected"
    assert names["orchard.rm"][0].children[0].name == "require FruitDetector"
    close(client, *(orchard / f for f in ("orchard.tsm", "orchard.fm", "orchard.rm")))


async def test_formatting_prints_with_spls_printer_and_keeps_comments(
    client: LanguageClient, tmp_path: Path
):
    fm = tmp_path / "shop.fm"
    text = "feature model Shop\nroot Shop {  optional   Search\n mandatory Payment }\n"
    open_file(client, fm, text)
    (edit,) = await client.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=types.TextDocumentIdentifier(uri(fm)),
            options=types.FormattingOptions(tab_size=4, insert_spaces=True),
        )
    )
    from spl.dsl.fm import language as fm_language
    from spl.dsl.fm.printer import print_model

    assert edit.new_text == print_model(fm_language.parse_text(text, str(fm)))
    change(client, fm, "// a comment\n" + text, 2)
    result = await client.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=types.TextDocumentIdentifier(uri(fm)),
            options=types.FormattingOptions(tab_size=4, insert_spaces=True),
        )
    )
    assert result is None
    assert "comments" in client.messages[-1].message
    close(client, fm)


async def test_half_typed_files_never_break_the_server(client: LanguageClient, orchard: Path):
    """Every prefix of the .rm (cut at a line) gets answers to every request."""
    rm = orchard / "orchard.rm"
    text = rm.read_text(encoding="utf-8")
    open_file(client, rm, "")
    cuts = [*[i for i, c in enumerate(text) if c == "\n"][::3], len(text) - 7]
    document = types.TextDocumentIdentifier(uri(rm))
    for version, cut in enumerate(cuts, start=2):
        partial = text[:cut] + " Sc"
        change(client, rm, partial, version)
        end = position_of(partial, " Sc", occurrence=partial.count(" Sc") - 1, shift=3)
        await client.text_document_completion_async(types.CompletionParams(document, end))
        await client.text_document_hover_async(types.HoverParams(document, end))
        await client.text_document_definition_async(types.DefinitionParams(document, end))
        await client.text_document_document_symbol_async(types.DocumentSymbolParams(document))
    found = await diagnostics(client, rm, lambda d: True)
    assert all(d.source == "spl" for d in found)
    change(client, rm, text, len(cuts) + 2)
    await diagnostics(client, rm, lambda d: d == [])
    close(client, rm)


async def test_an_unknown_request_is_answered_with_an_error_and_serving_goes_on(
    client: LanguageClient, orchard: Path
):
    with pytest.raises(Exception, match=r"(?i)method not found"):
        await client.protocol.send_request_async("spl/noSuchMethod", {})
    rm = orchard / "orchard.rm"
    open_file(client, rm)
    await diagnostics(client, rm, lambda d: d == [])
    close(client, rm)


class _Watched(BaseLanguageClient):
    """pygls's client, keeping how the server process ended."""

    returncode: int | None = None
    stderr = b""

    async def server_exit(self, server) -> None:
        self.returncode = server.returncode
        self.stderr = await server.stderr.read()


async def test_shutdown_and_exit_end_the_server_cleanly(tmp_path: Path):
    client = _Watched("test", "1")
    published = asyncio.Event()
    client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)(lambda *_: published.set())
    await client.start_io(sys.executable, "-m", "spl", "lsp")
    await client.initialize_async(
        types.InitializeParams(capabilities=types.ClientCapabilities(), root_uri=tmp_path.as_uri())
    )
    client.initialized(types.InitializedParams())
    fm = tmp_path / "shop.fm"
    fm.write_text("feature model Shop\nroot Shop { optional Search }\n", encoding="utf-8")
    open_file(client, fm)  # the checking thread is running
    await asyncio.wait_for(published.wait(), 60)
    assert await client.shutdown_async(None) is None
    client.exit(None)
    await asyncio.wait_for(client.stop(), 60)
    assert client.returncode == 0
    assert b"Traceback" not in client.stderr and b"ERROR" not in client.stderr


async def test_exit_without_shutdown_ends_with_status_1(tmp_path: Path):
    """The protocol's rule (pygls's own status was lost in an asyncio callback: 0)."""
    client = _Watched("test", "1")
    await client.start_io(sys.executable, "-m", "spl", "lsp")
    await client.initialize_async(
        types.InitializeParams(capabilities=types.ClientCapabilities(), root_uri=tmp_path.as_uri())
    )
    client.initialized(types.InitializedParams())
    client.exit(None)
    await asyncio.wait_for(client.stop(), 60)
    assert client.returncode == 1
    assert b"Traceback" not in client.stderr
