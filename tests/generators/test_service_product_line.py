"""The data-acquisition product line through the real Resolution Engine: each product
gets exactly the services, clients and deployment files of its features."""

from __future__ import annotations

import shutil

import pytest
import yaml

from spl.generators.clients import generator as clients
from spl.generators.deploy import generator as deploy
from spl.generators.service import generator as service
from spl.resolver.resolution.data_clients import client_package_name
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.service_models import PRODUCT_LINE

RESOLUTION = """\
resolution model DataAcquisition
tsm "data.tsm"
fm  "data.fm"
when Positions selected {
    require DataCloud.PositionStore, PositionWriter, PositionReader
}
when Follow selected {
    require DataCloud.FollowStore, VelocityWriter, CommandReader
}
"""


@pytest.fixture(scope="module")
def line(tmp_path_factory: pytest.TempPathFactory):  # type: ignore[no-untyped-def]
    directory = tmp_path_factory.mktemp("data_acquisition")
    for name in ("data.tsm", "data.fm"):
        shutil.copy(PRODUCT_LINE / name, directory / name)
    rm = PRODUCT_LINE / "data.rm"
    (directory / "data.rm").write_text(rm.read_text() if rm.exists() else RESOLUTION)
    return load_product_line(directory)


def bundle(line, features: str) -> dict[str, bytes]:  # type: ignore[no-untyped-def]
    product = resolve(line, selection_from_list(features, name="da")).product
    return {**service.generate(product), **clients.generate(product), **deploy.generate(product)}


def folders(files: dict[str, bytes]) -> set[str]:
    """A file's folder below the bundle (``clients/<flavour>/<package>`` for clients)."""
    return {
        "/".join(path.split("/")[: 3 if path.startswith("clients/") else 2])
        for path in files
        if path.count("/") >= 2
    }


def test_positions_on_sqlite(line) -> None:
    files = bundle(line, "Positions,Embedded")
    assert folders(files) == {
        "services/PositionStore",
        "clients/ros1/position_writer",
        "clients/ros2/position_writer",
        "clients/ros1/position_reader",
        "clients/ros2/position_reader",
        "deploy/PositionStore",
        "deploy/kubernetes",
    }
    compose = yaml.safe_load(files["deploy/docker-compose.yml"])
    assert set(compose["services"]) == {"position-store"}


def test_follow_on_postgres(line) -> None:
    files = bundle(line, "Follow,Postgres")
    assert folders(files) == {
        "services/FollowStore",
        "clients/ros1/velocity_writer",
        "clients/ros2/velocity_writer",
        "clients/ros1/command_reader",
        "clients/ros2/command_reader",
        "deploy/FollowStore",
        "deploy/kubernetes",
    }
    assert "deploy/kubernetes/postgres.yaml" in files
    settings = files["services/FollowStore/follow_store_service/settings.py"]
    assert b"postgresql://spl@localhost:5432/spl" in settings


def test_both_case_studies_in_one_product(line) -> None:
    files = bundle(line, "Positions,Follow,Embedded")
    assert {"services/PositionStore", "services/FollowStore"} <= folders(files)
    setup = files["clients/ros2/command_reader/setup.py"].decode()
    assert "'command_reader = command_reader.reader_node:main'" in setup


def test_resolver_and_client_generator_agree_on_package_names(line) -> None:
    product = resolve(line, selection_from_list("Positions,Follow,Embedded", name="da")).product
    for container in product.system.containers:
        for node in container.nodes:
            if node.eClass.name in ("Writer", "Reader"):
                assert node.package == client_package_name(node.name)
                assert f"clients/ros2/{node.package}/package.xml" in clients.generate(product)
