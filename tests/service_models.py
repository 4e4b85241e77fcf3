"""The data-acquisition system of product_lines/data_acquisition, for the service tests.

Parsed from data.tsm with the .tsm language when it is available; until then built
with the metamodel classes, mirroring that file element by element.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from spl.metamodels import tsm
from spl.resolver.product import ResolvedProduct

PRODUCT_LINE = Path(__file__).resolve().parents[1] / "product_lines" / "data_acquisition"


def _built_system() -> Any:
    T = tsm()
    system = T.System(name="DataAcquisition")

    def data(name: str, *fields: str) -> Any:
        dt = T.DataType(name=name)
        for f in fields:
            dt.fields.append(T.Field(name=f, type=T.FieldType.double))
        system.dataTypes.append(dt)
        return dt

    def ref(field: str, record: str = "") -> Any:
        return T.FieldReference(record=record, field=field)

    seconds = data("PositionInSecond", "lat", "lon")
    degrees = data("PositionInDEG", "lat", "lon")
    velocity = data("Velocity", "vx", "vy", "va")
    command = data("Command", "duration", "vx", "vy", "va")
    to_deg = T.Transform(name="SecondToDEG", input=seconds, output=degrees)
    for f in ("lat", "lon"):
        to_deg.assignments.append(T.Assignment(field=f, expression=T.BinaryExpression(
            operator="/", left=ref(f), right=T.NumberLiteral(value="3600.0"))))
    to_command = T.Transform(name="VelocityToCommand", input=velocity, output=command)
    to_command.assignments.append(T.Assignment(field="duration", expression=T.BinaryExpression(
        operator="-", left=ref("timestamp", "next"), right=ref("timestamp"))))
    for f in ("vx", "vy", "va"):
        to_command.assignments.append(T.Assignment(field=f, expression=ref(f)))
    system.transforms.extend([to_deg, to_command])

    cloud = T.CloudContainer(name="DataCloud", group="acquisition", endpoint=T.Endpoint())
    position_store = T.Store(name="PositionStore", optional=True, raw=seconds)
    position_store.refinements.append(T.Refinement(output=degrees, transform=to_deg, period=5.0))
    follow_store = T.Store(name="FollowStore", optional=True, raw=velocity)
    follow_store.refinements.append(
        T.Refinement(output=command, transform=to_command, period=1.0))
    cloud.stores.extend([position_store, follow_store])
    system.containers.append(cloud)

    def robot(name: str, robot_id: str) -> Any:
        container = T.RobotContainer(name=name, endpoint=T.Endpoint(
            robotId=robot_id, url="wss://cloud.example.org:9000/", user=robot_id.replace("_", ""),
            passwordEnv="RCE_PASSWORD"))
        system.containers.append(container)
        return container

    def topic(container: Any, name: str, type_: str, ros: str) -> Any:
        t = T.Topic(name=name, type=type_, rosName=ros)
        container.topics.append(t)
        return t

    rover = robot("Rover", "rover_1")
    gps_s = topic(rover, "GpsSeconds", "rover_msgs/PositionInSecond", "/gps/seconds")
    gps_d = topic(rover, "GpsDeg", "rover_msgs/PositionInDEG", "/gps/deg")
    writer = T.Writer(name="PositionWriter", optional=True, dataType=seconds,
                      store=position_store)
    writer.interfaces.append(T.Subscriber(name="records", type=gps_s.type, topic=gps_s))
    reader = T.Reader(name="PositionReader", optional=True, dataType=degrees,
                      store=position_store, period=1.0)
    reader.interfaces.append(T.Publisher(name="records", type=gps_d.type, topic=gps_d))
    rover.nodes.extend([writer, reader])

    ev3a = robot("EV3A", "ev3_a")
    vel = topic(ev3a, "VelocityChanges", "ev3_msgs/Velocity", "/ev3/velocity")
    vwriter = T.Writer(name="VelocityWriter", optional=True, dataType=velocity, store=follow_store)
    vwriter.interfaces.append(T.Subscriber(name="records", type=vel.type, topic=vel))
    ev3a.nodes.append(vwriter)

    ev3b = robot("EV3B", "ev3_b")
    cmd = topic(ev3b, "Commands", "ev3_msgs/Command", "/ev3/command")
    creader = T.Reader(name="CommandReader", optional=True, dataType=command, store=follow_store,
                       period=0.5)
    creader.interfaces.append(T.Publisher(name="records", type=cmd.type, topic=cmd))
    ev3b.nodes.append(creader)
    return system


def data_acquisition_system() -> Any:
    try:
        from spl.dsl import tsm as tsm_language
    except ImportError:
        return _built_system()
    return tsm_language.parse_file(PRODUCT_LINE / "data.tsm")


def product(
    name: str = "data_acquisition",
    features: tuple[str, ...] = ("DataAcquisition", "Embedded", "Follow", "Positions", "Storage"),
    attributes: dict[str, Any] | None = None,
    system: Any = None,
) -> ResolvedProduct:
    if attributes is None:
        attributes = {"Embedded.database": "sqlite", "Postgres.database": "postgresql"}
    return ResolvedProduct(
        name=name,
        system=system if system is not None else data_acquisition_system(),
        features=tuple(sorted(features)),
        attributes=attributes,
    )
