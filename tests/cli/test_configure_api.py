"""``spl configure``'s JSON API (docs/configure.md), through FastAPI's TestClient: the
acceptance flow on mapping3d, a bare UVL model, refusals (409 with the explanation, 422
for bad values, the selection unchanged), undo/redo, YAML export and import, capability
files, fleet mode, independent sessions, saving under a validated name, the bundle
zip equal to what ``spl resolve -o`` writes, and 413 for a body over the limit on every
endpoint that takes one (through a real server: tests/live/test_configure_body_limit.py)."""

from __future__ import annotations

import io
import json
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
import yaml
from fastapi.testclient import TestClient

from spl.configure.app import create_app
from spl.configure.body_limit import MAX_BODY
from spl.configure.workspace import load_fleet_workspace, load_workspace

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"


def client(source: Path) -> TestClient:
    return TestClient(create_app(load_workspace(source)))


def decide(api: TestClient, feature: str, action: str = "select"):
    return api.post("/api/decide", json={"feature": feature, "action": action})


def states(api: TestClient) -> dict[str, str]:
    return api.get("/api/state").json()["states"]


def test_selecting_additional_pc_implies_youbot_and_excludes_roomba_with_the_reason() -> None:
    api = client(MAPPING)
    before = api.get("/api/state").json()
    assert before["products"] == {"exact": True, "value": "12", "text": "12 products"}
    answer = decide(api, "AdditionalPC")
    assert answer.status_code == 200
    view = answer.json()
    # only the rows that changed are sent
    assert view["states"] == {
        "YouBot": "implied-selected",
        "Roomba": "implied-deselected",
        "AdditionalPC": "selected",
    }
    assert view["products"]["value"] == "4"
    assert answer.headers["Server-Timing"].startswith("app;dur=")
    why = api.get("/api/explain", params={"feature": "Roomba"}).json()["lines"]
    assert why[0] == "Roomba: feature not selected"
    assert "selecting Roomba contradicts your decisions (selecting AdditionalPC):" in why[1]
    assert "Roomba excludes AdditionalPC" in why[2] and "mapping.fm:29" in why[2]
    # a feature in every product is explained by the model, not by the decision
    assert api.get("/api/explain", params={"feature": "MobileBase"}).json()["lines"][1] == (
        "  deselecting MobileBase contradicts the feature model:"
    )
    youbot = api.get("/api/explain", params={"feature": "YouBot"}).json()["lines"]
    assert youbot[0] == "YouBot: selected feature"
    assert any("MobileBase: exactly one of YouBot, Roomba" in line for line in youbot)


def test_an_impossible_decision_is_a_409_with_the_explanation_and_changes_nothing() -> None:
    api = client(MAPPING)
    decide(api, "AdditionalPC")
    refused = decide(api, "Roomba")
    assert refused.status_code == 409
    explanation = refused.json()["explanation"]
    assert explanation[0] == "selecting AdditionalPC, Roomba contradicts:"
    assert "mapping.fm:29" in explanation[1]
    assert states(api)["Roomba"] == "implied-deselected"
    for bad in ({"feature": "Nope", "action": "select"}, {"feature": "Roomba", "action": "x"}):
        assert api.post("/api/decide", json=bad).status_code == 422


def test_completing_the_selection_draws_the_architecture_and_zips_the_bundle_as_resolve(
    tmp_path: Path,
) -> None:
    api = client(MAPPING)
    assert api.get("/api/architecture").status_code == 409  # not complete yet
    for feature in ("AdditionalPC", "Stereo", "Room"):
        decide(api, feature)
    view = api.get("/api/state").json()
    assert view["complete"] and view["products"]["value"] == "1"
    drawing = api.get("/api/architecture").json()
    assert drawing["svg"].startswith("<svg")
    assert 'data-container="Robot"' in drawing["svg"]
    assert 'data-migrated="MappingCloud"' in drawing["svg"]  # MapOptimizer moved on board
    assert 'data-node-removed="DepthCamera"' in drawing["svg"]
    exported = api.get("/api/selection.yaml")
    selection = tmp_path / "chosen.yaml"
    selection.write_bytes(exported.content)
    out = tmp_path / "bundle"
    subprocess.run(
        [sys.executable, "-m", "spl", "resolve", str(MAPPING), "--features", str(selection),
         "-o", str(out)],
        check=True, capture_output=True, cwd=tmp_path,
    )  # fmt: skip
    written = {
        str(path.relative_to(out)): path.read_bytes() for path in out.rglob("*") if path.is_file()
    }
    zipped = api.get("/api/bundle.zip")
    assert zipped.headers["content-type"] == "application/zip"
    with zipfile.ZipFile(io.BytesIO(zipped.content)) as archive:
        files = {name: archive.read(name) for name in archive.namelist()}
    assert sorted(files) == sorted(written)
    assert files == written


def test_a_bare_uvl_model_is_analysed_without_architecture() -> None:
    api = client(ROOT / "tests" / "data" / "feature-models" / "berkeleydb.uvl")
    view = api.get("/api/state").json()
    if not view["products"]["exact"]:  # past the quick budget: a labelled lower bound
        assert view["products"]["text"].startswith("at least ")
        assert "exact count not found within 0.005 s" in view["products"]["text"]
    counted = api.get("/api/count").json()["products"]
    assert counted == {"exact": True, "value": "4080389785", "text": "4080389785 products"}
    page = api.get("/")
    assert page.status_code == 200 and 'data-feature="BerkeleyDB"' in page.text
    assert "data-architecture" not in page.text
    opens = sorted(name for name, state in view["states"].items() if state == "open")
    answer = decide(api, opens[0])
    assert answer.status_code == 200
    assert int(answer.json()["products"]["value"]) < 4080389785
    assert api.get("/api/architecture").status_code == 422


def test_a_malformed_attribute_is_refused_with_the_type_and_the_selection_unchanged() -> None:
    api = client(ROOT / "product_lines" / "orchard")
    decide(api, "CloudDetection")
    before = api.get("/api/state").json()
    refused = api.post("/api/attribute", json={"key": "CloudDetection.threshold", "value": "high"})
    assert refused.status_code == 422
    assert refused.json()["error"] == "attribute CloudDetection.threshold is double, got 'high'"
    after = api.get("/api/state").json()
    assert after == before
    huge = api.post("/api/attribute", json={"key": "CloudDetection.threshold", "value": "1e999"})
    assert huge.status_code == 422  # out of a double's range
    assert (
        api.post("/api/attribute", json={"key": "Scouting.speed", "value": "1"}).json()["error"]
        == "unknown feature attribute Scouting.speed"
    )
    taken = api.post("/api/attribute", json={"key": "CloudDetection.threshold", "value": "0.7"})
    assert taken.status_code == 200 and taken.json()["attributes"] == {
        "CloudDetection.threshold": "0.7"
    }


def test_undo_and_redo_step_through_decisions_and_values() -> None:
    api = client(MAPPING)
    decide(api, "AdditionalPC")
    api.post("/api/sharing", json={"feature": "SharedMap", "mode": "private"})
    undone = api.post("/api/undo").json()
    assert undone["sharing"] == {} and undone["redo"]
    undone = api.post("/api/undo").json()
    assert states(api)["Roomba"] == "open" and not undone["undo"]
    assert api.post("/api/undo").status_code == 422  # nothing left to undo
    api.post("/api/redo")
    assert states(api)["Roomba"] == "implied-deselected"
    assert api.post("/api/redo").json()["sharing"] == {"SharedMap": "private"}


def test_yaml_round_trip_and_unknown_features_listed_at_their_place() -> None:
    api = client(MAPPING)
    for feature in ("AdditionalPC", "Stereo", "Room"):
        decide(api, feature)
    api.post("/api/sharing", json={"feature": "SharedMap", "mode": "public"})
    api.post("/api/deployment", json={"container": "Robot", "key": "robot_id", "value": "yb_7"})
    text = api.get("/api/selection.yaml", params={"name": "lab_robot"}).text
    assert yaml.safe_load(text) == {
        "product": "lab_robot",
        "features": ["AdditionalPC", "Stereo", "Room"],
        "sharing": {"SharedMap": "public"},
        "deployment": {"Robot": {"robot_id": "yb_7"}},
    }
    other = client(MAPPING)
    imported = other.post("/api/selection", json={"text": text, "filename": "lab.yaml"})
    assert imported.status_code == 200
    assert other.get("/api/selection.yaml", params={"name": "lab_robot"}).text == text
    bad = "product: p\nfeatures: [YouBot, Wheels]\ndeselected: [Lidar]\n"
    refused = other.post("/api/selection", json={"text": bad, "filename": "mine.yaml"})
    assert refused.status_code == 422
    assert refused.json()["problems"] == [
        "mine.yaml:2:20: error: unknown feature 'Wheels'",
        "mine.yaml:3:14: error: unknown feature 'Lidar'",
    ]
    assert other.get("/api/selection.yaml", params={"name": "lab_robot"}).text == text


def test_only_the_names_given_are_answered() -> None:
    app = create_app(load_workspace(MAPPING), ["127.0.0.1", "localhost"])
    assert TestClient(app, base_url="http://127.0.0.1:8765").get("/").status_code == 200
    refused = TestClient(app, base_url="http://rebound.example:8765").get("/api/state")
    assert refused.status_code == 400


def test_two_sessions_do_not_share_decisions() -> None:
    app = create_app(load_workspace(MAPPING))
    first, second = TestClient(app), TestClient(app)
    decide(first, "AdditionalPC")
    assert states(first)["Roomba"] == "implied-deselected"
    assert states(second)["Roomba"] == "open"


def test_sessions_are_bounded_the_least_recently_used_going_first() -> None:
    from spl.configure.app import SESSIONS

    app = create_app(load_workspace(MAPPING))
    first = TestClient(app)
    decide(first, "AdditionalPC")
    others = [TestClient(app) for _ in range(SESSIONS)]
    for other in others:
        other.get("/api/state")
    assert states(others[-1])["Roomba"] == "open"
    assert states(first)["Roomba"] == "open"  # its session was dropped: a fresh one


def test_a_capability_file_decides_features_as_resolve_capabilities_does() -> None:
    api = client(MAPPING)
    robot = MAPPING / "fleets" / "robots" / "youbot_1.yaml"
    answer = api.post(
        "/api/capabilities", json={"text": robot.read_text(), "filename": "youbot_1.yaml"}
    )
    assert answer.status_code == 200
    now = states(api)
    assert now["YouBot"] == "implied-selected" and now["AdditionalPC"] == "implied-selected"
    why = api.get("/api/explain", params={"feature": "YouBot"}).json()["lines"]
    assert why[1].startswith("  capability base: youbot (youbot_1.yaml:3:1) selects YouBot")
    refused = decide(api, "YouBot", "deselect")
    assert refused.status_code == 422 and "robot's capabilities" in refused.json()["error"]
    broken = api.post("/api/capabilities", json={"text": "base: [", "filename": "bad.yaml"})
    assert broken.status_code == 422 and broken.json()["error"].startswith("bad.yaml:")


def test_fleet_mode_locks_what_the_shared_instances_fix() -> None:
    workspace = load_fleet_workspace(MAPPING / "fleets" / "lab.yaml", "youbot_4", "lab")
    api = TestClient(create_app(workspace))
    now = states(api)
    assert now["Room"] == "implied-selected" and now["Corridor"] == "implied-deselected"
    why = api.get("/api/explain", params={"feature": "Corridor"}).json()["lines"]
    assert "the fleet forbids it: StrategyPlanner must have implementation" in why[1]
    refused = decide(api, "Corridor")
    assert refused.status_code == 422 and "decided by the fleet" in refused.json()["error"]
    assert api.get("/api/state").json()["products"]["value"] == "6"


def test_fleet_mode_starts_from_the_robots_entry() -> None:
    """A robot already in the fleet is being changed: its entry is the first state."""
    workspace = load_fleet_workspace(MAPPING / "fleets" / "lab.yaml", "roomba_2", None)
    view = TestClient(create_app(workspace)).get("/api/state").json()
    assert view["decisions"] == [
        {"feature": "Roomba", "value": True},
        {"feature": "Stereo", "value": True},
    ]
    assert view["sharing"] == {"SharedMap": "public"}
    assert view["deployment"] == {
        "Robot": {"robot_id": "roomba-cellar", "url": "wss://rce.example.org:9000/"}
    }
    assert view["complete"] and not view["undo"]
    robot = load_fleet_workspace(MAPPING / "fleets" / "lab.yaml", "youbot_1", None)
    start = TestClient(create_app(robot)).get("/api/state").json()
    assert start["capabilities"] == "youbot_1"  # its capability file decides its hardware
    assert start["states"]["YouBot"] == "implied-selected"


def test_saving_writes_only_products_name_yaml_under_a_valid_new_name(tmp_path: Path) -> None:
    line = tmp_path / "mapping3d"
    shutil.copytree(MAPPING, line)
    before = sorted(p.relative_to(line) for p in line.rglob("*"))
    api = client(line)
    decide(api, "AdditionalPC")
    for name in ("../escape", "a b", ""):
        assert api.post("/api/save", json={"name": name}).status_code == 422
    assert api.post("/api/save", json={"name": "youbot_stereo_room"}).status_code == 422  # exists
    assert sorted(p.relative_to(line) for p in line.rglob("*")) == before
    assert api.post("/api/save", json={"name": "pc_robot"}).json() == {
        "saved": "products/pc_robot.yaml"
    }
    saved = yaml.safe_load((line / "products" / "pc_robot.yaml").read_text())
    assert saved == {"product": "pc_robot", "features": ["AdditionalPC"]}


# every endpoint that takes a body, with a body it takes
BODIES = [
    ("/api/decide", {"feature": "AdditionalPC", "action": "select"}),
    ("/api/attribute", {"key": "AdditionalPC.cores", "value": "4"}),
    ("/api/sharing", {"feature": "SharedMap", "mode": "public"}),
    ("/api/deployment", {"container": "Robot", "key": "robot_id", "value": "r1"}),
    ("/api/selection", {"text": "product: p\nfeatures: [AdditionalPC]\n"}),
    ("/api/capabilities", {"text": "base: youbot\n"}),
    ("/api/save", {"name": "padded"}),
]


def padded(body: dict, size: int) -> bytes:
    """``body`` as JSON of exactly ``size`` bytes (spaces before its closing brace)."""
    text = json.dumps(body).encode()
    return text[:-1] + b" " * (size - len(text)) + b"}"


@pytest.mark.parametrize(("path", "body"), BODIES, ids=[p for p, _ in BODIES])
def test_every_body_over_the_limit_is_refused_with_413_and_changes_nothing(
    path: str, body: dict
) -> None:
    api = client(MAPPING)
    before = api.get("/api/state").json()
    headers = {"Content-Type": "application/json"}
    answer = api.post(path, content=padded(body, MAX_BODY + 1), headers=headers)
    assert answer.status_code == 413
    assert answer.json() == {
        "error": f"the request body has {MAX_BODY + 1} bytes; at most {MAX_BODY} are taken"
    }
    assert answer.headers["connection"] == "close"
    # without a Content-Length (chunked), counted as it is read
    chunks = padded(body, MAX_BODY + 1)
    streamed = api.post(path, content=iter([chunks[:1000], chunks[1000:]]), headers=headers)
    assert streamed.status_code == 413
    assert streamed.json() == {"error": f"the request body has more than {MAX_BODY} bytes"}
    assert api.get("/api/state").json() == before


@pytest.mark.parametrize("path", ["/api/undo", "/api/redo"])
def test_a_body_to_an_endpoint_that_takes_none_is_refused_or_not_read_on(path: str) -> None:
    api = client(MAPPING)
    decide(api, "AdditionalPC")
    headers = {"Content-Type": "application/json"}
    answer = api.post(path, content=padded({}, MAX_BODY + 1), headers=headers)
    assert answer.status_code == 413 and "at most" in answer.json()["error"]
    assert states(api)["AdditionalPC"] == "selected"  # not undone
    # chunked: answered without reading it, and the connection is closed, not read on
    chunks = padded({}, MAX_BODY + 1)
    streamed = api.post(path, content=iter([chunks[:1000], chunks[1000:]]), headers=headers)
    assert streamed.headers["connection"] == "close"
    assert streamed.status_code == (200 if path == "/api/undo" else 422)


def test_a_body_of_exactly_the_limit_is_taken() -> None:
    api = client(MAPPING)
    answer = api.post(
        "/api/decide",
        content=padded({"feature": "AdditionalPC", "action": "select"}, MAX_BODY),
        headers={"Content-Type": "application/json"},
    )
    assert answer.status_code == 200 and answer.json()["states"]["AdditionalPC"] == "selected"
    small = TestClient(create_app(load_workspace(MAPPING), max_body=100))
    refused = decide(small, "AdditionalPC" + "x" * 100)
    assert refused.status_code == 413 and "at most 100" in refused.json()["error"]


def test_the_command_refuses_bad_input_with_a_message(tmp_path: Path) -> None:
    from click.testing import CliRunner

    from spl.cli import main

    text = tmp_path / "notes.txt"
    text.write_text("x")
    runner = CliRunner()
    result = runner.invoke(main, ["configure", str(text), "--no-browser"])
    assert result.exit_code == 2 and "expected a product-line folder" in result.output
    result = runner.invoke(main, ["configure", str(MAPPING), "--robot", "r1"])
    assert result.exit_code == 2 and "--robot and --group go with --fleet" in result.output
    result = runner.invoke(main, ["configure", "--fleet", str(MAPPING / "fleets" / "lab.yaml")])
    assert result.exit_code == 2 and "--fleet needs --robot" in result.output
    import socket

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        port = str(taken.getsockname()[1])
        result = runner.invoke(main, ["configure", str(MAPPING), "--no-browser", "--port", port])
    assert result.exit_code == 1
    assert f"cannot listen on 127.0.0.1:{port}: Address already in use (choose another --port)" in (
        result.output
    )
    # an address not this machine's: the advice is about the host, not the port
    result = runner.invoke(main, ["configure", str(MAPPING), "--no-browser", "--host", "x..y"])
    assert result.exit_code == 1
    assert "cannot listen on x..y:8765: " in result.output
    assert result.output.rstrip().endswith("(give one of this machine's addresses as --host)")


@pytest.mark.parametrize("line", sorted(p.name for p in (ROOT / "product_lines").iterdir()))
def test_every_shipped_line_serves_its_page(line: str) -> None:
    api = client(ROOT / "product_lines" / line)
    page = api.get("/")
    assert page.status_code == 200
    assert page.text.count("data-feature=") == len(api.get("/api/state").json()["states"])
