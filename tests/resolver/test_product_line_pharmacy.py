"""The shipped hospital-pharmacy line against architectures worked out by hand from
pharmacy.tsm, pharmacy.fm and pharmacy.rm (not from spl's output): where every node
runs, the endpoint connections (bridges), which publishers' data reaches every
subscriber, which real server answers every service client, the sharing mode of every
cloud node and the parameters the resolution model sets.

Bridges are written by container and ROS name (`Cart:/diagnostics ->
FacilityCloud:/diagnostics`), so a topic the endpoint rewiring creates is named by what
the documentation fixes about it (its container and ROS name), not by its model name."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import load_selection_file

LINE = Path(__file__).resolve().parents[2] / "product_lines" / "pharmacy"

CART = {
    "Lidar",
    "BaseDriver",
    "Navigator",
    "DeliveryExecutive",
    "BadgeReader",
    "DrawerController",
    "HandoverController",
}
DISPENSER = {"TrayCamera", "ArmDriver", "PickController"}


@pytest.fixture(scope="module")
def line():
    return load_product_line(LINE)


def product(line, name: str):
    return resolve(line, load_selection_file(LINE / "products" / f"{name}.yaml")).product


# ---- reading the resolved model -----------------------------------------------------


def container_of(element: Any) -> Any:
    while element.eClass.name not in ("RobotContainer", "CloudContainer"):
        element = element.eContainer()
    return element


def on_endpoint(interface: Any) -> bool:
    return interface.eContainer().eClass.name == "Endpoint"


def name_of(interface: Any) -> str:
    """`Container.Node.interface` of a node's interface, where the node runs now."""
    node = interface.eContainer()
    return f"{container_of(node).name}.{node.name}.{interface.name}"


def placement(system: Any) -> dict[str, set[str]]:
    return {c.name: {n.name for n in c.nodes} for c in system.containers}


def node_interfaces(system: Any, kind: str) -> list[Any]:
    return [
        i for c in system.containers for n in c.nodes for i in n.interfaces if i.eClass.name == kind
    ]


def bridges(system: Any) -> set[str]:
    """A topic bridge as `Container:/ros/name -> Container:/ros/name`; a service bridge
    as the calling side's container and the real server behind the endpoint client."""
    found = set()
    for connection in system.connections:
        source, target = connection.source, connection.target
        side = container_of(source).name
        if source.eClass.name == "ServiceServer":
            found.add(f"{side} -> {name_of(real_server(target))}")
        else:
            found.add(
                f"{side}:{source.topic.rosName} -> "
                f"{container_of(target).name}:{target.topic.rosName}"
            )
    return found


def feeders(system: Any, subscriber: Any) -> set[str]:
    """The node publishers whose messages reach `subscriber`: those on its topic, and,
    for every endpoint publisher on it, those behind the endpoint connection feeding
    it, recursively."""
    found: set[str] = set()
    seen: set[int] = set()
    todo = [subscriber.topic] if subscriber.topic is not None else []
    while todo:
        topic = todo.pop()
        if id(topic) in seen:
            continue
        seen.add(id(topic))
        container = container_of(topic)
        publishers = [i for n in container.nodes for i in n.interfaces] + list(
            container.endpoint.interfaces
        )
        for publisher in publishers:
            if publisher.eClass.name != "Publisher" or publisher.topic is not topic:
                continue
            if not on_endpoint(publisher):
                found.add(name_of(publisher))
                continue
            for connection in system.connections:
                if connection.target is publisher:
                    todo.append(connection.source.topic)
    return found


def real_server(client: Any) -> Any:
    """The node server answering `client`, behind any chain of endpoint stand-ins."""
    server = client.server
    hops = 0
    while server is not None and on_endpoint(server):
        (connection,) = [c for c in system_of(server).connections if c.source is server]
        server = connection.target.server
        hops += 1
        assert hops < 10, "a loop of endpoint stand-ins"
    return server


def system_of(element: Any) -> Any:
    while element.eContainer() is not None:
        element = element.eContainer()
    return element


def data_flows(system: Any) -> dict[str, set[str]]:
    return {name_of(s): feeders(system, s) for s in node_interfaces(system, "Subscriber")}


def service_flows(system: Any) -> dict[str, str | None]:
    result = {}
    for client in node_interfaces(system, "ServiceClient"):
        server = real_server(client)
        result[name_of(client)] = None if server is None else name_of(server)
    return result


def cloud_sharing(system: Any) -> dict[str, str]:
    return {
        f"{c.name}.{n.name}": n.sharing.name
        for c in system.containers
        if c.eClass.name == "CloudContainer"
        for n in c.nodes
    }


def nodes_by_name(system: Any) -> dict[str, Any]:
    return {f"{c.name}.{n.name}": n for c in system.containers for n in c.nodes}


def param(node: Any, name: str) -> str | None:
    (parameter,) = [p for p in node.parameters if p.name == name]
    return parameter.value


def topics(system: Any, container: str) -> set[str]:
    (c,) = [c for c in system.containers if c.name == container]
    return {t.rosName for t in c.topics}


# ---- what both products share --------------------------------------------------------

# the cart's own graph and what it gets from and gives to the clouds, identical in both
# products (badge access, TUG base)
CART_FLOWS = {
    "Cart.Navigator.scan": {"Cart.Lidar.scan"},
    "Cart.Navigator.odom": {"Cart.BaseDriver.odom"},
    "Cart.Navigator.goal": {"Cart.DeliveryExecutive.goal"},
    "Cart.BaseDriver.cmd_vel": {"Cart.Navigator.cmd_vel"},
    # the order queue's jobs, bridged down from the pharmacy cloud
    "Cart.DeliveryExecutive.jobs": {"PharmacyCloud.OrderManager.delivery_jobs"},
    # fan-out, first branch: the facility cloud's alerts
    "Cart.DeliveryExecutive.alerts": {"FacilityCloud.FireAlarmGateway.alerts"},
    "Cart.HandoverController.credential": {"Cart.BadgeReader.credential"},
}

DISPENSER_FLOWS = {
    "Dispenser.ArmDriver.command": {"Dispenser.PickController.command"},
    "Dispenser.PickController.orders": {"PharmacyCloud.OrderManager.dispense_orders"},
    "Dispenser.PickController.joint_states": {"Dispenser.ArmDriver.joint_states"},
    # fan-out, second branch
    "Dispenser.PickController.alerts": {"FacilityCloud.FireAlarmGateway.alerts"},
}

# fan-in: the custody trail of both robots, and both robots' diagnostics
CUSTODY = {"Cart.HandoverController.custody", "Dispenser.PickController.custody"}
DIAGNOSTICS = {"Cart.BaseDriver.diagnostics", "Dispenser.ArmDriver.diagnostics"}

SERVICES = {
    "Cart.HandoverController.unlock": "Cart.DrawerController.unlock",
    # one verifier answers clients of two containers
    "Cart.HandoverController.verify": "PharmacyCloud.MedicationVerifier.verify",
    "Dispenser.PickController.verify": "PharmacyCloud.MedicationVerifier.verify",
}

TEMPLATE_BRIDGES = {
    # fan-out
    "FacilityCloud:/facility/alerts -> Cart:/facility/alerts",
    "FacilityCloud:/facility/alerts -> Dispenser:/facility/alerts",
    # fan-in
    "Cart:/pharmacy/custody_events -> PharmacyCloud:/pharmacy/custody_events",
    "Dispenser:/pharmacy/custody_events -> PharmacyCloud:/pharmacy/custody_events",
    "Cart:/diagnostics -> FacilityCloud:/diagnostics",
    "Dispenser:/diagnostics -> FacilityCloud:/diagnostics",
    # the order queue
    "PharmacyCloud:/pharmacy/delivery_jobs -> Cart:/pharmacy/delivery_jobs",
    "PharmacyCloud:/pharmacy/dispense_orders -> Dispenser:/pharmacy/dispense_orders",
    # the shared verifier
    "Cart -> PharmacyCloud.MedicationVerifier.verify",
    "Dispenser -> PharmacyCloud.MedicationVerifier.verify",
}


# ---- the products ---------------------------------------------------------------------


def test_reference_hospital_cloud_inspection(line):
    """tug_badge_audit: TUG cart, badge access, pills inspected in the cloud, custody
    audit (public by default), per-robot diagnostics aggregators (private)."""
    p = product(line, "tug_badge_audit")
    system = p.system
    assert placement(system) == {
        "Cart": CART,
        "Dispenser": DISPENSER,
        "PharmacyCloud": {
            "OrderManager",
            "MedicationVerifier",
            "PillInspector",
            "CustodyAuditor",
        },
        "FacilityCloud": {"FireAlarmGateway", "DiagnosticAggregator"},
    }
    assert bridges(system) == TEMPLATE_BRIDGES | {
        # the tray images go up to the inspector, its results come back to the arm
        "Dispenser:/tray_camera/image_raw -> PharmacyCloud:/tray_camera/image_raw",
        "PharmacyCloud:/pharmacy/pill_inspection -> Dispenser:/pharmacy/pill_inspection",
    }
    assert data_flows(system) == {
        **CART_FLOWS,
        **DISPENSER_FLOWS,
        "Dispenser.PickController.inspection": {"PharmacyCloud.PillInspector.inspection"},
        "PharmacyCloud.PillInspector.image": {"Dispenser.TrayCamera.image"},
        "PharmacyCloud.CustodyAuditor.events": CUSTODY,
        "PharmacyCloud.CustodyAuditor.inspections": {"PharmacyCloud.PillInspector.inspection"},
        "FacilityCloud.DiagnosticAggregator.diagnostics": DIAGNOSTICS,
    }
    assert service_flows(system) == SERVICES
    assert cloud_sharing(system) == {
        "PharmacyCloud.OrderManager": "public",  # .tsm
        "PharmacyCloud.MedicationVerifier": "public",  # Verification's default
        "PharmacyCloud.PillInspector": "protected",  # .tsm
        "PharmacyCloud.CustodyAuditor": "public",  # CustodyAudit's default
        "FacilityCloud.FireAlarmGateway": "public",  # .tsm
        "FacilityCloud.DiagnosticAggregator": "private",  # one per robot
    }
    # the inventory tracker is off: its restock topic goes with it
    assert "/pharmacy/restock_requests" not in topics(system, "PharmacyCloud")
    nodes = nodes_by_name(system)
    assert (nodes["Cart.BaseDriver"].package, nodes["Cart.BaseDriver"].executable) == (
        "aethon_tug",
        "tug_base_driver",
    )
    assert float(param(nodes["PharmacyCloud.PillInspector"], "confidence")) == 0.9
    assert param(nodes["PharmacyCloud.PillInspector"], "model") == "pill_classifier.onnx"
    assert int(param(nodes["PharmacyCloud.CustodyAuditor"], "retention_days")) == 3650
    assert param(nodes["Cart.DrawerController"], "witness_required") == "false"
    assert param(nodes["Dispenser.PickController"], "count_back") == "false"
    assert not p.warnings


def test_controlled_substances_edge_inspection(line):
    """narcotics_edge_full: the pill inspector migrates onto the dispenser (next to the
    tray camera and the arm), the auditor gets its results through a new bridge, the
    inventory tracker listens to a topic of the dispenser (T2), every monitoring
    feature is on."""
    p = product(line, "narcotics_edge_full")
    system = p.system
    assert placement(system) == {
        "Cart": CART,
        "Dispenser": DISPENSER | {"PillInspector"},
        "PharmacyCloud": {
            "OrderManager",
            "MedicationVerifier",
            "CustodyAuditor",
            "InventoryTracker",
        },
        "FacilityCloud": {"FireAlarmGateway", "DiagnosticAggregator", "BlackBoxRecorder"},
    }
    assert bridges(system) == TEMPLATE_BRIDGES | {
        # the inspector's results now flow up, to the auditor only; the tray images no
        # longer leave the dispenser and the template's downward bridge is gone
        "Dispenser:/pharmacy/pill_inspection -> PharmacyCloud:/pharmacy/pill_inspection",
        # `connect ... to topic Dispenser.Dispensed` from the cloud (T2)
        "Dispenser:/dispenser/dispensed -> PharmacyCloud:/dispenser/dispensed",
    }
    assert data_flows(system) == {
        **CART_FLOWS,
        **DISPENSER_FLOWS,
        "Dispenser.PickController.inspection": {"Dispenser.PillInspector.inspection"},
        "Dispenser.PillInspector.image": {"Dispenser.TrayCamera.image"},
        "PharmacyCloud.CustodyAuditor.events": CUSTODY,
        "PharmacyCloud.CustodyAuditor.inspections": {"Dispenser.PillInspector.inspection"},
        "PharmacyCloud.InventoryTracker.dispensed": {"Dispenser.PickController.dispensed"},
        "FacilityCloud.DiagnosticAggregator.diagnostics": DIAGNOSTICS,
        "FacilityCloud.BlackBoxRecorder.diagnostics": DIAGNOSTICS,
        "FacilityCloud.BlackBoxRecorder.alerts": {"FacilityCloud.FireAlarmGateway.alerts"},
    }
    assert service_flows(system) == SERVICES
    assert cloud_sharing(system) == {
        "PharmacyCloud.OrderManager": "public",
        "PharmacyCloud.MedicationVerifier": "public",
        "PharmacyCloud.CustodyAuditor": "public",
        "PharmacyCloud.InventoryTracker": "protected",  # .tsm
        "FacilityCloud.FireAlarmGateway": "public",
        "FacilityCloud.DiagnosticAggregator": "private",
        "FacilityCloud.BlackBoxRecorder": "private",
    }
    # the cloud's tray-image topic lost every interface; the tracker's input is a topic
    # of the cloud under the dispenser's ROS name; the restock topic stays
    pharmacy_topics = topics(system, "PharmacyCloud")
    assert "/tray_camera/image_raw" not in pharmacy_topics
    assert {"/dispenser/dispensed", "/pharmacy/restock_requests"} <= pharmacy_topics
    nodes = nodes_by_name(system)
    inspector = nodes["Dispenser.PillInspector"]
    assert param(inspector, "model") == "pill_yolov8n_int8.onnx"
    assert float(param(inspector, "confidence")) == 0.95
    assert int(param(nodes["PharmacyCloud.CustodyAuditor"], "retention_days")) == 9125
    assert param(nodes["Cart.DrawerController"], "witness_required") == "true"
    assert param(nodes["Dispenser.PickController"], "count_back") == "true"
    (image,) = [i for i in inspector.interfaces if i.name == "image"]
    assert container_of(image.topic).name == "Dispenser"
    assert not p.warnings
