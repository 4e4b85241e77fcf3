"""The name-resolution rules of docs/semantics.md, one test (or more) per rule, on the
farm line of tests/models/semantics: a tractor and a drone that both have a node Camera
and a topic Images, and a cloud whose Detector and Planner can move onto the tractor.

Each test writes its own .rm next to copies of farm.tsm and farm.fm; statements start on
line 5 of that file (after the three header lines and one `when` line)."""

from __future__ import annotations

import shutil
import textwrap
from pathlib import Path

import pytest
from click.testing import CliRunner
from lxml import etree

from spl.cli import main
from spl.core.diagnostics import ModelError
from spl.dsl.rm import language as rm
from spl.resolver.line_checks import check_product_line
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.architecture_view import view

MODELS = Path(__file__).parents[1] / "models" / "semantics"
HEADER = 'resolution model Farm\ntsm "farm.tsm"\nfm  "farm.fm"\n'


def farm(tmp_path: Path, body: str, tsm: str | None = None) -> Path:
    """A copy of the farm line with ``body`` as its resolution elements."""
    (tmp_path / "farm.tsm").write_text(tsm or (MODELS / "farm.tsm").read_text())
    shutil.copy(MODELS / "farm.fm", tmp_path / "farm.fm")
    (tmp_path / "farm.rm").write_text(HEADER + textwrap.dedent(body))
    return tmp_path


def element(feature: str, *statements: str) -> str:
    """``when FEATURE selected { ... }`` with one statement a line, from line 5 on."""
    return "".join([f"when {feature} selected {{\n", *(f"    {s}\n" for s in statements), "}\n"])


def parse_errors(tmp_path: Path, body: str, tsm: str | None = None) -> list[str]:
    """The .rm's parse errors, paths relative to the line's folder."""
    farm(tmp_path, body, tsm)
    with pytest.raises(ModelError) as caught:
        rm.load(tmp_path / "farm.rm")
    return [str(d).replace(f"{tmp_path}/", "") for d in caught.value.diagnostics]


def product(tmp_path: Path, body: str, features: str):
    line = load_product_line(farm(tmp_path, body))
    return resolve(line, selection_from_list(features)).product


def resolution_errors(tmp_path: Path, body: str, features: str) -> list[str]:
    line = load_product_line(farm(tmp_path, body))
    with pytest.raises(ModelError) as caught:
        resolve(line, selection_from_list(features))
    return [str(d).replace(f"{tmp_path}/", "") for d in caught.value.diagnostics]


def run(*args: str):
    return CliRunner().invoke(main, list(args))


def remaps(bundle: Path, container: str) -> dict[str, dict[str, str]]:
    """``{node: {interface: ROS name}}`` of one ROS 1 launch file of a bundle."""
    root = etree.parse(str(bundle / "ros1" / f"{container}.launch")).getroot()
    return {
        node.get("name"): {r.get("from"): r.get("to") for r in node.iter("remap")}
        for node in root.iter("node")
    }


# -- two defects as a user met them ----------------------------------------
MIGRATE_THEN_CONNECT = """\
    when OnBoard selected {
        connect Tractor.Camera.thumbs to new topic Thumbs : sensor_msgs/Image name "/camera/thumbs"
        migrate Detector to Tractor
        connect Detector.thumbs to topic Thumbs
    }
"""


def test_regression_topic_created_then_node_migrated_and_connected_in_one_element(tmp_path):
    """Before: ``farm.rm:7:5: error: unknown topic Thumbs in container Cloud`` (the engine
    looked the topic up where the node is in the template)."""
    line = farm(tmp_path, MIGRATE_THEN_CONNECT)
    checked = run("check", str(line))
    assert checked.exit_code == 0, checked.output
    assert "unknown topic Thumbs in container Cloud" not in checked.output
    out = tmp_path / "bundle"
    resolved = run("resolve", str(line), "--features", "OnBoard", "-o", str(out))
    assert resolved.exit_code == 0, resolved.output
    assert "unknown topic" not in resolved.output
    assert remaps(out, "Tractor") == {
        "Camera": {"image": "/camera/image", "thumbs": "/camera/thumbs"},
        "Navigator": {"cmd": "/cmd_vel"},
        "Driver": {"cmd": "/cmd_vel"},
        "Detector": {"image": "/camera/image", "thumbs": "/camera/thumbs", "weeds": "/weeds"},
    }
    assert not (out / "ros1" / "Cloud.launch").exists()  # left with no node
    system = view(load_resolved(line, "OnBoard"))
    # the drone's images still reach the Detector, now on the tractor
    assert system["bridges"] == ["Drone.endpoint.sub_Images -> Tractor.endpoint.pub_Images"]


def load_resolved(line: Path, features: str):
    return resolve(load_product_line(line), selection_from_list(features)).product.system


BRIDGE_TO_CREATED = """\
    when Thumbs selected {
        connect Tractor.Camera.thumbs to new topic Thumbs : sensor_msgs/Image name "/camera/thumbs"
        connect Detector.thumbs to new topic Thumbs : sensor_msgs/Image name "/camera/thumbs"
        connect bridge Tractor.Thumbs -> Cloud.Thumbs
    }
"""


def test_regression_bridge_to_topics_created_in_the_same_element(tmp_path):
    """Before: ``error: internal error in spl 0.1.0: KeyError: ...`` (context.copy_of: the
    created topic has no template original), exit 3."""
    line = farm(tmp_path, BRIDGE_TO_CREATED)
    out = tmp_path / "bundle"
    resolved = run("resolve", str(line), "--features", "Thumbs", "-o", str(out))
    assert resolved.exit_code == 0, resolved.output
    assert "internal error" not in resolved.output and "KeyError" not in resolved.output
    assert remaps(out, "Cloud")["Detector"]["thumbs"] == "/camera/thumbs"
    assert remaps(out, "Tractor")["Camera"]["thumbs"] == "/camera/thumbs"
    bridges = view(load_resolved(line, "Thumbs"))["bridges"]
    assert "Tractor.endpoint.sub_Thumbs -> Cloud.endpoint.pub_Thumbs" in bridges
    assert run("check", str(line)).exit_code == 0


# -- N: nodes -----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "statement",
    [
        "require Camera",
        "implementation Camera = usb_cam/usb_cam_node",
        "migrate Camera to Cloud",
        "connect Camera.thumbs to new topic Small : sensor_msgs/Image",
        "connect Camera.image to topic Images",
    ],
)
def test_node_declared_in_two_containers_must_be_qualified(tmp_path, statement):
    """N2: an unqualified name declared in two containers names both candidates."""
    errors = parse_errors(tmp_path, element("Thumbs", statement))
    assert errors == [
        "farm.rm:5:5: error: Camera is ambiguous: node Tractor.Camera (farm.tsm:14:10) or "
        "node Drone.Camera (farm.tsm:40:10); qualify it with its container"
    ]
    qualified = statement.replace("Camera", "Tractor.Camera", 1)
    farm(tmp_path, element("Thumbs", qualified))
    rm.load(tmp_path / "farm.rm")


def test_node_qualifier_is_the_declaring_container_wherever_it_moves(tmp_path):
    """N3: ``CONTAINER.NODE`` names the container that declares the node in the .tsm."""
    errors = parse_errors(
        tmp_path,
        """\
        when OnBoard selected {
            migrate Cloud.Detector to Tractor
            parameter Tractor.Detector.threshold = 0.7
            parameter Cloud.Detector.threshold = 0.7
        }
        """,
    )
    assert errors == [
        "farm.rm:6:5: error: no node Detector is declared in container Tractor (Detector is "
        "declared in Cloud; a node is qualified by the container that declares it, wherever "
        "migrations move it)"
    ]


def test_every_statement_takes_qualified_names(tmp_path):
    """N4 and S1: the qualified form of each statement kind, and a client connected to a
    server that a migration earlier in the element brought into its container."""
    resolved = product(
        tmp_path,
        """\
        when Planning selected {
            require Cloud.Planner
            implementation Cloud.Planner = farm_nav/field_planner
            migrate Cloud.Planner to Tractor
            connect Cloud.Planner.route to topic Tractor.Route
            connect Tractor.Navigator.route to topic Route
            connect Tractor.Navigator.plan to server Cloud.Planner.plan
            parameter Tractor.Navigator.rate = 5.0
        }
        """,
        "Planning",
    )
    v = view(resolved.system)
    assert v["placement"]["Planner"] == "Tractor"
    assert v["bindings"]["Navigator.plan"] == "Planner.plan"  # served locally, no bridge
    assert v["bindings"]["Planner.route"] == v["bindings"]["Navigator.route"] == "Tractor.Route"
    planner = next(n for c in resolved.system.containers for n in c.nodes if n.name == "Planner")
    assert planner.executable == "field_planner"
    navigator = next(
        n for c in resolved.system.containers for n in c.nodes if n.name == "Navigator"
    )
    assert navigator.parameters[0].value == "5.0"
    # the Planner's weeds come from the cloud's Detector through the endpoints
    assert v["bridges"] == [
        "Cloud.endpoint.sub_Weeds -> Tractor.endpoint.pub_Weeds",
        "Drone.endpoint.sub_Images -> Cloud.endpoint.pub_Images",
        "Tractor.endpoint.sub_Images -> Cloud.endpoint.pub_Images",
    ]


def test_migration_into_a_container_with_a_node_of_that_name_is_refused(tmp_path):
    """N5, statically and, when another element moved the other node there, on resolving."""
    errors = parse_errors(tmp_path, element("OnBoard", "migrate Drone.Camera to Tractor"))
    assert errors == [
        "farm.rm:5:5: error: cannot migrate Camera to Tractor: container Tractor already has "
        "a node Camera (farm.tsm:14:10)"
    ]
    body = """\
    when OnBoard selected {
        migrate Tractor.Camera to Cloud
    }
    when Thumbs selected {
        migrate Drone.Camera to Cloud
    }
    """
    assert len(product(tmp_path, body, "OnBoard").migrations) == 1
    assert resolution_errors(tmp_path, body, "OnBoard,Thumbs") == [
        "farm.rm:8:5: error: cannot migrate Camera to Cloud: container Cloud already has a "
        "node Camera (farm.tsm:14:10)"
    ]


# -- T: topics ----------------------------------------------------------------------------
def test_unqualified_topic_is_looked_up_where_the_node_is_at_that_statement(tmp_path):
    """T1: before the migration the Planner is in the cloud, which has no topic Route."""
    errors = parse_errors(
        tmp_path,
        """\
        when Planning selected {
            connect Planner.route to topic Route
            migrate Planner to Tractor
            connect Planner.route to topic Route
        }
        """,
    )
    assert errors == ["farm.rm:5:5: error: unknown topic Route in container Cloud"]


def test_migration_of_an_earlier_element_moves_the_lookup(tmp_path):
    """T1 across elements: statically the Planner can be in Cloud or Tractor; resolved, it
    is where the active elements put it, and a product that leaves it in the cloud is
    refused at the statement."""
    body = """\
    when LocalPlanning selected {
        migrate Planner to Tractor
    }
    when Planning selected {
        require Planner
        connect Planner.route to topic Route
        connect Navigator.route to topic Route
    }
    """
    local = view(product(tmp_path, body, "Planning,LocalPlanning").system)
    assert local["bindings"]["Planner.route"] == "Tractor.Route"
    assert resolution_errors(tmp_path, body, "Planning") == [
        "farm.rm:9:5: error: unknown topic Route in container Cloud, where Planner is at this point"
    ]
    missing = parse_errors(tmp_path, body.replace("topic Route\n", "topic Nowhere\n", 1))
    assert missing == [
        "farm.rm:9:5: error: unknown topic Nowhere in container Cloud or Tractor (where "
        "Planner can be at this point)"
    ]


def test_qualified_topic_of_another_container_is_carried_by_the_endpoints(tmp_path):
    """T2: ``CONTAINER.TOPIC`` names that container's topic, wherever the node is."""
    v = view(
        product(
            tmp_path,
            """\
            when Planning selected {
                connect Planner.route to topic Tractor.Route
                connect Navigator.route to topic Route
            }
            """,
            "Planning",
        ).system
    )
    assert v["placement"]["Planner"] == "Cloud"
    assert v["bindings"]["Planner.route"] == "Cloud.Route"  # a local mirror, /route
    assert "Cloud.endpoint.sub_Route -> Tractor.endpoint.pub_Route" in v["bridges"]
    errors = parse_errors(
        tmp_path,
        """\
        when Planning selected {
            connect Planner.route to topic Drone.Route
            connect Planner.route to topic Barn.Route
            connect Planner.route to topic Farm.Tractor.Route
        }
        """,
    )
    assert errors == [
        "farm.rm:5:5: error: unknown topic Route in container Drone",
        "farm.rm:6:5: error: unknown container Barn",
        "farm.rm:7:5: error: Farm.Tractor.Route: expected TOPIC or CONTAINER.TOPIC",
    ]


def test_created_topic_exists_only_after_the_statement_creating_it(tmp_path):
    """T3: a `new topic` is seen by later statements and later elements, not earlier ones."""
    errors = parse_errors(
        tmp_path,
        """\
        when Thumbs selected {
            connect Detector.thumbs to topic Thumbs
        }
        when OnBoard selected {
            connect Detector.thumbs to new topic Thumbs : sensor_msgs/Image
        }
        when Planning selected {
            connect Detector.thumbs to topic Thumbs
        }
        """,
    )
    assert errors == ["farm.rm:5:5: error: unknown topic Thumbs in container Cloud"]


def test_new_topic_is_created_where_the_node_is_and_shared_when_declared_alike(tmp_path):
    """T3: created in the node's container at that point; a second alike declaration is the
    same topic; an unlike one, or one over a .tsm topic, is refused."""
    v = view(
        product(
            tmp_path,
            """\
            when OnBoard selected {
                migrate Detector to Tractor
                connect Detector.thumbs to new topic Small : sensor_msgs/Image name "/small"
            }
            when Thumbs selected {
                connect Tractor.Camera.thumbs to new topic Small : sensor_msgs/Image name "/small"
            }
            """,
            "OnBoard,Thumbs",
        ).system
    )
    assert v["bindings"]["Detector.thumbs"] == "Tractor.Small"
    assert v["topics"]["Tractor"].count("Small") == 1
    errors = parse_errors(
        tmp_path,
        """\
        when OnBoard selected {
            connect Detector.thumbs to new topic Small : sensor_msgs/Image name "/small"
            connect Detector.thumbs to new topic Small : sensor_msgs/Image name "/other"
            connect Detector.thumbs to new topic Images : sensor_msgs/Image
        }
        """,
    )
    assert errors == [
        "farm.rm:6:5: error: new topic Small in Cloud is declared again with another type or "
        "ROS name (first at farm.rm:5:5)",
        "farm.rm:7:5: error: new topic Images: container Cloud already has a topic named "
        "Images (farm.tsm:47:11; connect to it with 'to topic Images')",
    ]


def test_bridge_end_is_read_by_the_model(tmp_path):
    """B1: ``X.Y`` in a bridge is topic Y of container X or interface Y of node X."""
    v = view(
        product(
            tmp_path,
            """\
            when Planning selected {
                connect bridge Navigator.plan -> Planner.plan
                connect bridge Cloud.Images -> Drone.Images
            }
            """,
            "Planning",
        ).system
    )
    assert v["bindings"]["Navigator.plan"] == "Tractor.endpoint.srv_Planner_plan"
    errors = parse_errors(
        tmp_path, element("Planning", "connect bridge Cloud.Weeds -> Drone.Images")
    )
    assert errors == [
        "farm.rm:5:5: error: type mismatch: Weeds is std_msgs/String, Images is sensor_msgs/Image"
    ]


def test_bridge_end_naming_a_topic_and_an_interface_is_ambiguous(tmp_path):
    """B1: a container Navigator with a topic plan makes ``Navigator.plan`` two things."""
    tsm = (MODELS / "farm.tsm").read_text() + (
        "\ncloud container Navigator {\n"
        '    topic plan : farm_msgs/Plan name "/plan"\n'
        "    node Relay { implementation relay/relay  subscribes plan <- plan }\n"
        "}\n"
    )
    errors = parse_errors(
        tmp_path,
        element("Planning", "connect bridge Navigator.plan -> Planner.plan"),
        tsm,
    )
    assert errors == [
        "farm.rm:5:5: error: Navigator.plan is ambiguous: topic plan of container Navigator "
        "(farm.tsm:70:11) or interface plan of node Navigator (farm.tsm:25:20)"
    ]


def test_services_follow_the_containers_of_their_nodes_at_that_point(tmp_path):
    """S1, S2: `to server` needs one container, a bridge two, as the statements before
    left them; statically when certain, else when a product is resolved."""
    errors = parse_errors(
        tmp_path,
        """\
        when Planning selected {
            connect Navigator.plan to server Planner.plan
            migrate Planner to Tractor
            connect bridge Navigator.plan -> Planner.plan
        }
        """,
    )
    assert errors == [
        "farm.rm:5:5: error: Planner.plan is served in container Cloud, not in Tractor: use "
        "'connect bridge Tractor.Navigator.plan -> Cloud.Planner.plan'",
        "farm.rm:7:5: error: a bridge connects two different containers: Navigator.plan and "
        "Planner.plan are both in Tractor at this point (connect them with 'to server')",
    ]
    body = """\
    when LocalPlanning selected {
        migrate Planner to Tractor
    }
    when Planning selected {
        connect Navigator.plan to server Planner.plan
    }
    """
    assert (
        view(product(tmp_path, body, "LocalPlanning,Planning").system)["bindings"]["Navigator.plan"]
        == "Planner.plan"
    )
    assert resolution_errors(tmp_path, body, "Planning") == [
        "farm.rm:8:5: error: Planner.plan is served in container Cloud, not in Tractor: use "
        "'connect bridge Tractor.Navigator.plan -> Cloud.Planner.plan' (containers at this "
        "point)"
    ]


# -- P: parameters ------------------------------------------------------------------------
SOIL = """\
system Soil
data Raw { x : double }
data Fine { x : double }
transform Refine : Raw -> Fine { x = x }
cloud container Soil {
    store Soil {
        raw Raw
        refined Fine by Refine every 5 s
    }
    node Fine {
        implementation soil/fine
        param period : double = 1.0
    }
}
"""


def test_parameter_or_refinement_period_is_ambiguous_when_both_exist(tmp_path):
    """P1: ``X.Y.period`` is node Y's parameter period in container X, or the period of
    store X's refinement into Y."""
    (tmp_path / "soil.tsm").write_text(SOIL)
    (tmp_path / "soil.fm").write_text("feature model Soil\nroot Soil { optional Fast }\n")
    (tmp_path / "soil.rm").write_text(
        'resolution model Soil\ntsm "soil.tsm"\nfm "soil.fm"\nwhen Fast selected {\n'
        "    parameter Soil.Fine.period = 2.0\n"
        "    parameter Fine.period = 2.0\n"
        "    parameter Soil.Soil.Fine.period = 2.0\n"
        "}\n"
    )
    with pytest.raises(ModelError) as caught:
        rm.load(tmp_path / "soil.rm")
    assert [str(d).replace(f"{tmp_path}/", "") for d in caught.value.diagnostics] == [
        "soil.rm:5:5: error: Soil.Fine.period is ambiguous: the period of store Soil's "
        "refinement into Fine (soil.tsm:8:17) or parameter period of node Fine (soil.tsm:12:15)"
    ]


# -- L: product-line checks ---------------------------------------------------------------
def test_line_conflicts_compare_topics_by_container_and_name(tmp_path):
    """L1: one topic named with and without its container is no conflict; two containers'
    topics, or two names, are."""
    line = load_product_line(
        farm(
            tmp_path,
            """\
            when Thumbs selected {
                connect Detector.image to topic Images
            }
            when OnBoard selected {
                connect Detector.image to topic Cloud.Images
            }
            when Planning selected {
                connect Detector.image to topic Tractor.Images
            }
            """,
        )
    )
    conflicts = [d for d in check_product_line(line, products=False) if d.code == "SPL012"]
    assert [(d.location.line, d.message.split(";")[0]) for d in conflicts] == [
        (
            11,
            f"conflict: 'when Planning selected' ({tmp_path}/farm.rm:10:1) gives topic "
            f"Tractor.Images to Detector.image, but 'when {feature}' ({tmp_path}/farm.rm:{at}:1) "
            f"gives Cloud.Images (at {tmp_path}/farm.rm:{at + 1}:5)",
        )
        for feature, at in (("OnBoard selected", 7), ("Thumbs selected", 4))
    ]


def findings(tmp_path: Path, body: str, code: str = "SPL016") -> list[str]:
    line = load_product_line(farm(tmp_path, body))
    return [
        str(d).replace(f"{tmp_path}/", "")
        for d in check_product_line(line, products=False)
        if d.code == code
    ]


def test_line_check_finds_a_topic_missing_in_some_products(tmp_path):
    """C3 (SPL016): the lookup of test_migration_of_an_earlier_element_moves_the_lookup,
    found by `spl check` with the product that fails; no finding once the feature model
    makes the migration come with the statement."""
    body = """\
    when LocalPlanning selected {
        migrate Planner to Tractor
    }
    when Planning selected {
        connect Planner.route to topic Route
    }
    """
    assert findings(tmp_path, body) == [
        "farm.rm:8:5: error: unknown topic Route in container Cloud, where Planner is at this "
        "point, in the product Farm, Planning [SPL016]"
    ]
    assert (
        findings(
            tmp_path,
            body.replace(
                "Planning selected {\n        connect", "LocalPlanning selected {\n        connect"
            ),
        )
        == []
    )


def test_line_check_finds_a_topic_created_by_an_element_that_may_be_off(tmp_path):
    """C3 (SPL016): a topic another element creates, by name and in a bridge."""
    body = """\
    when OnBoard selected {
        connect Detector.thumbs to new topic Thumbs : sensor_msgs/Image name "/thumbs"
        connect Tractor.Camera.thumbs to new topic Thumbs : sensor_msgs/Image name "/thumbs"
    }
    when Planning selected {
        connect Detector.thumbs to topic Thumbs
        connect bridge Tractor.Thumbs -> Cloud.Thumbs
        connect bridge Drone.Images -> Cloud.Thumbs
    }
    """
    assert findings(tmp_path, body) == [
        "farm.rm:9:5: error: unknown topic Thumbs in container Cloud, where Detector is at this "
        "point, in the product Farm, Planning [SPL016]",
        "farm.rm:10:5: error: unknown topic Thumbs in container Cloud, in the product Farm, "
        "Planning [SPL016]",
        "farm.rm:10:5: error: unknown topic Thumbs in container Tractor, in the product Farm, "
        "Planning [SPL016]",
        # one end always there, the other not: each end is its own question
        "farm.rm:11:5: error: unknown topic Thumbs in container Cloud, in the product Farm, "
        "Planning [SPL016]",
    ]
    assert resolution_errors(tmp_path, body, "Planning")[0] == (
        "farm.rm:9:5: error: unknown topic Thumbs in container Cloud, where Detector is at this "
        "point"
    )
    together = body.replace("OnBoard selected", "Farm selected")  # the root: always active
    assert findings(tmp_path, together) == []


def test_line_check_finds_services_apart_or_together_in_some_products(tmp_path):
    """C3 (SPL016) for S1, S2 and N5."""
    body = """\
    when LocalPlanning selected {
        migrate Planner to Tractor
    }
    when Planning selected {
        connect Navigator.plan to server Planner.plan
    }
    when Thumbs selected {
        connect bridge Navigator.plan -> Planner.plan
    }
    when OnBoard selected {
        migrate Tractor.Camera to Cloud
    }
    when Thumbs selected {
        migrate Drone.Camera to Cloud
    }
    """
    assert findings(tmp_path, body) == [
        "farm.rm:8:5: error: Planner.plan is served in container Cloud, not in Tractor: use "
        "'connect bridge Tractor.Navigator.plan -> Cloud.Planner.plan' (containers at this "
        "point), in the product Farm, Planning [SPL016]",
        "farm.rm:11:5: error: a bridge connects two different containers: Navigator.plan and "
        "Planner.plan are both in Tractor at this point (connect them with 'to server'), in "
        "the product Farm, LocalPlanning, Planning, Thumbs [SPL016]",
        "farm.rm:17:5: error: cannot migrate Camera to Cloud: container Cloud already has a "
        "node Camera (farm.tsm:14:10), in the product Farm, OnBoard, Thumbs [SPL016]",
    ]
    assert resolution_errors(tmp_path, body, "OnBoard,Thumbs") == [
        "farm.rm:17:5: error: cannot migrate Camera to Cloud: container Cloud already has a "
        "node Camera (farm.tsm:14:10)"
    ]


def test_a_syntax_error_naming_the_end_of_the_file_says_so_the_same_every_time():
    # was: "expected <arpeggio.EndOfFile object at 0x7f0742eeb850>, when", the address
    # differing from run to run
    text = HEADER + 'fm "farm.fm"\n'
    messages = set()
    for _ in range(2):
        with pytest.raises(ModelError) as caught:
            rm.parse_text(text, "farm.rm", base=MODELS)
        messages.add(str(caught.value.diagnostics[0]))
    assert messages == {"farm.rm:4:1: error: syntax error: expected end of file, when"}


# -- a new topic under a ROS name another type has ----------------------------------------
ROS_CLASH = (
    "new topic {name} is /cmd_vel in container Tractor, as topic Cmd is (farm.tsm:11:11), "
    "but carries sensor_msgs/Image, not geometry_msgs/Twist: one ROS topic carries one "
    "message type"
)


def test_a_new_topic_under_a_ros_name_of_another_type_is_refused(tmp_path):
    # was: spl check passed; the products activating it failed resolve (SPL044)
    errors = parse_errors(
        tmp_path,
        element(
            "Thumbs",
            'connect Tractor.Camera.thumbs to new topic Thumbs : sensor_msgs/Image name "/cmd_vel"',
        ),
    )
    assert errors == ["farm.rm:5:5: error: " + ROS_CLASH.format(name="Thumbs")]


def test_a_new_topic_under_a_ros_name_an_earlier_new_topic_took_is_refused(tmp_path):
    errors = parse_errors(
        tmp_path,
        element(
            "Thumbs",
            'connect Tractor.Camera.thumbs to new topic Thumbs : sensor_msgs/Image name "/t"',
            'connect Tractor.Navigator.route to new topic Plan : nav_msgs/Path name "/t"',
        ),
    )
    assert errors == [
        "farm.rm:6:5: error: new topic Plan is /t in container Tractor, as topic Thumbs is "
        "(farm.rm:5:5), but carries nav_msgs/Path, not sensor_msgs/Image: one ROS topic "
        "carries one message type"
    ]


def test_a_new_topic_sharing_a_ros_name_with_a_topic_of_its_type_is_accepted(tmp_path):
    statement = "connect Tractor.Camera.thumbs to new topic Thumbs : sensor_msgs/Image"
    body = element("Thumbs", statement + ' name "/camera/image"')
    resolved = product(tmp_path, body, "Thumbs")  # one ROS topic, as two topics of the .tsm
    assert view(resolved.system)["bindings"]["Camera.thumbs"] == "Tractor.Thumbs"


def test_a_ros_name_clash_in_some_places_only_fails_the_products_that_meet_it(tmp_path):
    # Detector may run on the tractor (OnBoard), where /cmd_vel is a Twist; in the cloud the
    # name is free: the statement stands, and the product moving Detector fails to resolve
    body = element("OnBoard", "migrate Detector to Tractor") + element(
        "Thumbs", 'connect Detector.thumbs to new topic Small : sensor_msgs/Image name "/cmd_vel"'
    )
    assert product(tmp_path, body, "Thumbs").system is not None
    errors = resolution_errors(tmp_path, body, "OnBoard,Thumbs")
    assert any("/cmd_vel" in e and "[SPL044]" in e for e in errors), errors
