"""architecture.svg of the resolved mapping product, read back as SVG."""

from __future__ import annotations

import re

import pytest
from lxml import etree

from spl.core.emf import copy_model
from spl.generators.diagrams import architecture as diagrams, graphviz_output
from spl.metamodels import tsm
from spl.metamodels.interface_kinds import KINDS

from support.launch_system import mapping_product

SVG = {"s": "http://www.w3.org/2000/svg"}


@pytest.fixture(scope="module")
def product():
    return mapping_product()


@pytest.fixture(scope="module")
def svg(product):
    return diagrams.generate(product)["architecture.svg"]


def texts(root: etree._Element) -> list[str]:
    return [t.text for t in root.iterfind(".//s:text", SVG) if t.text]


def group(root: etree._Element, kind: str, title: str) -> etree._Element:
    (found,) = [
        g
        for g in root.iterfind(f".//s:g[@class='{kind}']", SVG)
        if g.findtext("s:title", namespaces=SVG) == title
    ]
    return found


def test_names_every_element(product, svg):
    root = etree.fromstring(svg)
    shown = texts(root)
    words = set(shown)
    for container in product.system.containers:
        assert any(container.name in t for t in shown)
        for topic in container.topics:
            assert topic.name in words
        for node in container.nodes:
            assert node.name in words
            for interface in node.interfaces:
                assert interface.name in words
        for interface in container.endpoint.interfaces:
            assert interface.name in words
    assert "«robot container» Robot" in words
    assert "«cloud container» MappingCloud" in words


def test_containers_are_clusters_styled_by_kind(svg):
    root = etree.fromstring(svg)
    robot = group(root, "cluster", "cluster_Robot").find("s:path", SVG)
    cloud = group(root, "cluster", "cluster_MappingCloud").find("s:path", SVG)
    assert robot.get("fill") != cloud.get("fill")
    assert cloud.get("stroke-dasharray") and not robot.get("stroke-dasharray")


def test_fig4_colours_for_interfaces_topics_endpoints(svg):
    root = etree.fromstring(svg)
    fills = {p.get("fill") for p in root.iterfind(".//s:polygon", SVG)}
    for colour in (
        # a kind of a family not on every legend (an action's) is shown where the product
        # has one (tests/generators/test_action_outputs.py); this product has none
        [kind.colour for kind in KINDS if kind.family.in_every_legend],
        [diagrams.NODE_GREY, diagrams.TOPIC_GREEN, diagrams.ENDPOINT_ORANGE],
    ):
        assert set(colour) <= fills
    topic = group(root, "node", "Robot.topic.RGBImg").find("s:polygon", SVG)
    assert topic.get("fill") == diagrams.TOPIC_GREEN


def test_edges_for_data_flow_services_and_bridges(product, svg):
    root = etree.fromstring(svg)
    edges = {
        g.findtext("s:title", namespaces=SVG): g
        for g in root.iterfind(".//s:g[@class='edge']", SVG)
    }
    # publisher -> topic -> subscriber
    assert "Robot.node.StereoVision:i_rgb->Robot.topic.RGBImg" in edges
    assert "Robot.topic.RGBImg->Robot.endpoint:i_sub_RGBImg" in edges
    # server -> client, labelled with the ROS name the client reaches
    service = edges["MappingCloud.node.Database:i_get_map->MappingCloud.node.MapMerger:i_get_map"]
    assert service.findtext("s:text", namespaces=SVG) == "/db/get_map"
    stand_in = edges[
        "Robot.endpoint:i_srv_Database_update_poses->Robot.node.MapOptimizer:i_update_poses"
    ]
    assert stand_in.findtext("s:text", namespaces=SVG) == "update_poses"
    # one dashed edge per endpoint connection, labelled and titled with the flows it
    # carries (the flow table's rows)
    dashed = {t: g for t, g in edges.items() if g.find(".//s:path", SVG).get("stroke-dasharray")}
    assert len(dashed) == len(product.system.connections) == 7
    pose = dashed["Robot.endpoint:i_sub_PoseUpdated->MappingCloud.endpoint:i_pub_PoseUpdated"]
    assert pose.findtext(".//s:text", namespaces=SVG) == "1 flow"
    title = pose.find(".//s:a", SVG).get("{http://www.w3.org/1999/xlink}title")
    assert title == (
        "Robot.MapOptimizer.pose_updated -> MappingCloud.StrategyPlanner.pose_updated via "
        "Robot.PoseUpdated -> MappingCloud.PoseUpdated"
    )


def test_migration_and_sharing_are_marked(svg):
    root = etree.fromstring(svg)
    optimizer = group(root, "node", "Robot.node.MapOptimizer")
    assert "migrated from MappingCloud" in texts(optimizer)
    assert any(p.get("stroke") == diagrams.MIGRATED_RED for p in optimizer.iter("{*}polygon"))
    database = group(root, "node", "MappingCloud.node.Database")
    assert "«protected»" in texts(database)
    assert "«private»" in texts(group(root, "node", "Robot.node.RobotDriver"))
    assert "migrated from" not in " ".join(texts(group(root, "node", "Robot.node.RobotDriver")))


def test_deterministic_svg_without_tool_version(product, svg):
    again = mapping_product()
    again.system = copy_model(again.system)
    assert diagrams.generate(again)["architecture.svg"] == svg
    assert b"Generated by graphviz" not in svg
    assert not re.search(rb"20\d\d-\d\d-\d\d", svg)


def test_template_without_product(product):
    graph = diagrams.architecture_graph(product.system)
    data = graphviz_output.render_bytes(graph, "svg")
    assert b"migrated from" not in data and b"MapOptimizer" in data


def test_render_by_suffix_atomically(product, tmp_path):
    graph = diagrams.architecture_graph(product.system, product)
    png = graphviz_output.render(graph, tmp_path / "out" / "arch.png")
    assert png.read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
    svg = graphviz_output.render(graph, tmp_path / "arch.svg")
    etree.fromstring(svg.read_bytes())
    source = graphviz_output.render(graph, tmp_path / "arch.dot")
    assert source.read_text(encoding="utf-8") == graph.source
    with pytest.raises(ValueError, match=r"only render \.svg, \.png or \.dot"):
        graphviz_output.render(graph, tmp_path / "arch.pdf")
    names = ["arch.dot", "arch.png", "arch.svg", "out"]
    assert sorted(p.name for p in tmp_path.rglob("*")) == names


def test_model_text_is_shown_literally():
    product = mapping_product()
    product.system.containers[1].group = 'mappers\\N <i>"x"</i> & \\l'
    product.name = "p\\G"
    svg = diagrams.generate(product)["architecture.svg"]
    shown = texts(etree.fromstring(svg))
    assert 'group mappers\\N <i>"x"</i> & \\l' in shown
    assert "Mapping3D — product p\\G" in shown


def test_stores_writers_and_readers():
    T = tsm()
    system = T.System(name="DataAcquisition")
    raw = T.DataType(name="PositionInSecond")
    refined = T.DataType(name="PositionInDEG")
    system.dataTypes.extend([raw, refined])
    cloud = T.CloudContainer(name="DataCloud", endpoint=T.Endpoint())
    store = T.Store(name="PositionStore", raw=raw)
    cloud.stores.append(store)
    rover = T.RobotContainer(name="Rover", endpoint=T.Endpoint(robotId="rover_1"))
    gps = T.Topic(name="GpsSeconds", type="rover_msgs/PositionInSecond", rosName="/gps/seconds")
    rover.topics.append(gps)
    writer = T.Writer(name="PositionWriter", dataType=raw, store=store)
    writer.package = writer.executable = "position_writer"
    writer.interfaces.append(T.Subscriber(name="input", type=gps.type, topic=gps))
    reader = T.Reader(name="PositionReader", dataType=refined, store=store, period=1.0)
    reader.package = reader.executable = "position_reader"
    rover.nodes.extend([writer, reader])
    system.containers.extend([cloud, rover])
    svg = graphviz_output.render_bytes(diagrams.architecture_graph(system), "svg")
    root = etree.fromstring(svg)
    edges = {
        g.findtext("s:title", namespaces=SVG) for g in root.iterfind(".//s:g[@class='edge']", SVG)
    }
    assert "Rover.node.PositionWriter->DataCloud.store.PositionStore" in edges
    assert "DataCloud.store.PositionStore->Rover.node.PositionReader" in edges
    assert "Rover.topic.GpsSeconds->Rover.node.PositionWriter:i_input" in edges
    assert {"«writer»", "«reader»", "PositionStore"} <= set(texts(root))


def test_bundle_carries_the_source_of_its_diagram(product):
    """architecture.dot is the diagram: dot renders it to architecture.svg's bytes."""
    import subprocess

    files = diagrams.generate(product)
    drawn = subprocess.run(
        ["dot", "-Tsvg"], input=files["architecture.dot"], capture_output=True, check=True
    ).stdout
    assert re.sub(rb"<!-- Generated by graphviz[^>]*-->\n", b"", drawn) == files["architecture.svg"]
