"""Names of what is generated from stores and data clients: unique per (container,
element) in one bundle, deterministic, valid where they land, and unchanged where
nothing is shared.

The regression: two cloud containers each holding a store ``PositionStore`` shared
``services/PositionStore/`` (one service silently overwrote the other's files), one
Dockerfile, one Kubernetes Deployment and one database; two robot containers' writers
``PositionWriter`` shared ``clients/position_writer/``.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from spl.core.diagnostics import ModelError
from spl.generators.bundle.options import BundleOptions
from spl.generators.bundle.paths import BundleFiles, BundlePathClash, check_paths
from spl.generators.bundle.writer import build_bundle
from spl.generators.clients import generator as clients
from spl.resolver.architecture.generated_names import dns_name, unique_names
from spl.resolver.architecture.stores import store_errors, store_names, store_relations
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.cli_outcome import LOCATED_ERROR, run
from support.service_runtime import (
    TOKEN,
    RunningService,
    load_module,
    request,
    wait_for,
    write_files,
)

DNS_1035 = re.compile(r"[a-z]([-a-z0-9]{0,61}[a-z0-9])?\Z")
TYPES = """
data Position {
    lat : double
    lon : double
}
data PositionDeg {
    lat : double
    lon : double
}
transform ToDeg : Position -> PositionDeg {
    lat = lat / 3600.0
    lon = lon / 3600.0
}
"""


def robot(name: str, writes_to: str) -> str:
    return f"""
robot container {name} {{
    endpoint robot_id "{name.lower()}_1" url "wss://cloud.example.org:9000/" user "{name.lower()}"
             password env "RCE_PASSWORD"
    topic Gps : rover_msgs/Position name "/gps"
    node Gps {{
        implementation rover_gps/gps_publisher
        publishes fix -> Gps
    }}
    writer PositionWriter : Position to {writes_to} <- Gps
}}
"""


def line(folder: Path, clouds: str, robots: str = "", types: str = TYPES) -> Path:
    """A one-feature product line whose .tsm holds ``types``, ``clouds`` and ``robots``."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "n.tsm").write_text(f"system Names\n{types}{clouds}{robots}", encoding="utf-8")
    (folder / "n.fm").write_text("feature model Names\nroot Base {\n}\n", encoding="utf-8")
    (folder / "n.rm").write_text(
        'resolution model Names\ntsm "n.tsm"\nfm "n.fm"\n', encoding="utf-8"
    )
    return folder


def cloud(name: str, *stores: tuple[str, int]) -> str:
    body = "".join(
        f"    store {store} {{\n        raw Position\n"
        f"        refined PositionDeg by ToDeg every {period} s\n    }}\n"
        for store, period in stores
    )
    return f"cloud container {name} {{\n{body}}}\n"


def bundle_of(folder: Path) -> dict[str, bytes]:
    resolution = resolve(load_product_line(folder), selection_from_list("Base"))
    return build_bundle(resolution.product, BundleOptions(render_diagrams=False)).files


@pytest.fixture(scope="module")
def two_clouds(tmp_path_factory: pytest.TempPathFactory) -> dict[str, bytes]:
    clouds = cloud("FieldCloud", ("PositionStore", 5)) + cloud("LabCloud", ("PositionStore", 2))
    robots = robot("Rover", "FieldCloud.PositionStore") + robot("Tester", "LabCloud.PositionStore")
    return bundle_of(line(tmp_path_factory.mktemp("two") / "line", clouds, robots))


def folders(files: dict[str, bytes], top: str) -> list[str]:
    """The folders right below ``top`` (``services``, ``clients/ros1``, ...)."""
    depth = top.count("/") + 1
    return sorted({path.split("/")[depth] for path in files if path.startswith(f"{top}/")})


def test_stores_of_one_name_in_two_containers_get_a_service_each(two_clouds) -> None:
    assert folders(two_clouds, "services") == [
        "FieldCloud_PositionStore",
        "LabCloud_PositionStore",
    ]
    field = two_clouds[
        "services/FieldCloud_PositionStore/field_cloud_position_store_service/model.py"
    ].decode()
    lab = two_clouds[
        "services/LabCloud_PositionStore/lab_cloud_position_store_service/model.py"
    ].decode()
    # each service is its own store's: the transformer periods of the model (5 s, 2 s)
    assert "settings.period(5.0)" in field and "settings.period(2.0)" in lab
    assert "STORE = 'FieldCloud_PositionStore'" in field
    assert "'field_cloud_position_store_raw'" in field and "'lab_cloud_position_store_raw'" in lab


def test_each_store_is_deployed_on_its_own(two_clouds) -> None:
    assert folders(two_clouds, "deploy") == [
        "FieldCloud_PositionStore",
        "LabCloud_PositionStore",
        "README.md",
        "docker-compose.yml",
        "kubernetes",
    ]
    compose = yaml.safe_load(two_clouds["deploy/docker-compose.yml"])
    assert sorted(compose["services"]) == ["field-cloud-position-store", "lab-cloud-position-store"]
    urls = {s["environment"]["DATABASE_URL"] for s in compose["services"].values()}
    assert urls == {
        "sqlite:////data/field_cloud_position_store.db",
        "sqlite:////data/lab_cloud_position_store.db",
    }
    tokens = {
        variable
        for s in compose["services"].values()
        for variable in s["environment"]
        if variable.endswith("_TOKEN")
    }
    assert tokens == {"FIELD_CLOUD_POSITION_STORE_TOKEN", "LAB_CLOUD_POSITION_STORE_TOKEN"}
    names = []
    for path in ("field-cloud-position-store", "lab-cloud-position-store"):
        for document in yaml.safe_load_all(two_clouds[f"deploy/kubernetes/{path}.yaml"]):
            names.append((document["kind"], document["metadata"]["name"]))
    # Deployment, PersistentVolumeClaim, Service and NetworkPolicy of each store
    assert len(names) == len(set(names)) == 8
    assert all(DNS_1035.match(name.removesuffix("-data")) for _, name in names)
    dockerfile = two_clouds["deploy/LabCloud_PositionStore/Dockerfile"].decode()
    assert "COPY services/LabCloud_PositionStore/ /app/" in dockerfile


def test_writers_of_one_name_in_two_robots_get_a_package_each(two_clouds) -> None:
    assert folders(two_clouds, "clients/ros1") == [
        "rover_position_writer",
        "tester_position_writer",
    ]
    assert folders(two_clouds, "clients/ros2") == folders(two_clouds, "clients/ros1")
    for container, package, store in (
        ("Rover", "rover_position_writer", "FieldCloud_PositionStore"),
        ("Tester", "tester_position_writer", "LabCloud_PositionStore"),
    ):
        launch = two_clouds[f"ros2/{container}.launch.xml"].decode()
        assert f'pkg="{package}" exec="{package}" name="PositionWriter"' in launch
        module = two_clouds[f"clients/ros2/{package}/{package}/store_client.py"].decode()
        assert f"STORE = {store!r}" in module
    manifest = yaml.safe_load(two_clouds["manifest.json"])
    assert len(manifest["files"]) == len(two_clouds) - 1


def test_the_two_services_keep_their_records_apart(two_clouds, tmp_path: Path) -> None:
    root = write_files(two_clouds, tmp_path)
    running = []
    try:
        for key, slug in (
            ("FieldCloud_PositionStore", "field_cloud_position_store"),
            ("LabCloud_PositionStore", "lab_cloud_position_store"),
        ):
            env = {f"{slug.upper()}_TOKEN": TOKEN, f"{slug.upper()}_TRANSFORM_PERIOD": "0.1"}
            running.append(RunningService(root / "services" / key, f"{slug}_service", env).start())
        field, lab = running
        writer = load_module(
            root / "clients/ros2/rover_position_writer/rover_position_writer/store_client.py",
            "rover_position_writer_client",
        )
        writer.StoreClient(field.url, token=TOKEN).post(
            [writer.to_record("rover_1", 1.0, {"lat": 3600.0, "lon": 7200.0})]
        )

        def refined(service: RunningService, key: str) -> list | None:
            items = request("GET", f"{service.url}/{key}/PositionDeg?from=0&to=10")[2]["items"]
            return items or None

        assert [
            (r["lat"], r["lon"])
            for r in wait_for(lambda: refined(field, "FieldCloud_PositionStore"))
        ] == [(1.0, 2.0)]
        assert (
            request("GET", f"{lab.url}/LabCloud_PositionStore/PositionDeg?from=0&to=10")[2]["items"]
            == []
        )
    finally:
        for service in running:
            service.stop()


def test_a_store_alone_keeps_its_plain_names(tmp_path: Path) -> None:
    files = bundle_of(
        line(
            tmp_path / "one",
            cloud("FieldCloud", ("PositionStore", 5)),
            robot("Rover", "FieldCloud.PositionStore"),
        )
    )
    assert folders(files, "services") == ["PositionStore"]
    assert "deploy/kubernetes/position-store.yaml" in files
    assert folders(files, "clients/ros1") == folders(files, "clients/ros2") == ["position_writer"]


def test_names_that_meet_in_one_container_are_told_apart(tmp_path: Path) -> None:
    """``PositionStore`` and ``Position_Store`` give one package, ``Postgres`` the
    deployment's own database's name, ``A`` refining ``PositionDeg`` a table of
    ``A_Position``... whatever meets, each store still gets its own of everything."""
    clouds = cloud(
        "DataCloud",
        ("PositionStore", 1),
        ("Position_Store", 2),
        ("Postgres", 3),
        ("A", 4),
        ("A_Position", 5),
        ("S" + "x" * 80, 6),
    ) + cloud("Data", ("Cloud_PositionStore", 7))
    folder = line(tmp_path / "meet", clouds)
    system = load_product_line(folder).tsm
    names = store_names(system)
    stores = [s for c in system.containers for s in c.stores]
    slugs = [names[id(s)].slug for s in stores]
    dns = [names[id(s)].dns for s in stores]
    keys = [names[id(s)].key.lower() for s in stores]
    tables = [t for s in stores for t, _ in store_relations(names[id(s)].slug, s)]
    assert len(set(slugs)) == len(set(dns)) == len(set(keys)) == len(stores)
    assert len(set(tables)) == len(tables)
    assert max(len(t) for t in tables) <= 63  # PostgreSQL would cut longer ones silently
    assert "postgres" not in dns and all(DNS_1035.match(d) for d in dns)
    assert all(s.isidentifier() and s[0].isalpha() for s in slugs)
    files = bundle_of(folder)
    check_paths(files)
    assert len(folders(files, "services")) == len(stores)
    assert bundle_of(folder) == files  # deterministic


def test_unique_names_rule() -> None:
    def forms(_: object, name: str) -> set[str]:
        return {name.lower()}

    elements = [(1, "A", "Store"), (2, "B", "Store"), (3, "C", "Other"), (4, "A", "b_store")]
    # b_store would meet B_Store's qualified name: it is qualified too
    assert unique_names(elements, forms) == ["A_Store", "B_Store", "Other", "A_b_store"]
    # qualified names meeting again are numbered, in model order
    elements = [(1, "A_B", "C"), (2, "A", "B_C"), (3, "Q", "c"), (4, "R", "b_c")]
    assert unique_names(elements, forms) == ["A_B_C", "A_B_C_2", "Q_c", "R_b_c"]
    assert unique_names([(1, "C", "Postgres")], forms, frozenset({"postgres"})) == ["C_Postgres"]
    long = dns_name("S" + "x" * 80)
    assert len(long) == 63 and DNS_1035.match(long) and long != dns_name("S" + "x" * 81)


def test_two_writers_naming_one_package_are_refused_with_a_location(tmp_path: Path) -> None:
    robots = robot("Rover", "FieldCloud.PositionStore") + robot(
        "Tester", "FieldCloud.PositionStore"
    )
    robots = robots.replace(
        "<- Gps\n", "<- Gps {\n        implementation shared_writer/writer\n    }\n"
    )
    folder = line(tmp_path / "given", cloud("FieldCloud", ("PositionStore", 5)), robots)
    product = resolve(load_product_line(folder), selection_from_list("Base")).product
    with pytest.raises(ModelError) as error:
        clients.generate(product)
    (diagnostic,) = error.value.diagnostics
    assert "both run package shared_writer" in diagnostic.message
    assert diagnostic.location is not None and diagnostic.location.line > 0


def test_bundle_files_refuse_a_second_file_for_one_path() -> None:
    files = BundleFiles({"services/S/README.md": b"one"})
    with pytest.raises(BundlePathClash, match=r"services/S/README\.md"):
        files["services/S/README.md"] = b"two"
    with pytest.raises(BundlePathClash):
        files.update({"clients/p/setup.py": b"", "services/S/README.md": b"three"})
    with pytest.raises(BundlePathClash):
        BundleFiles([("a", b"1"), ("a", b"2")])
    assert files["services/S/README.md"] == b"one"


@pytest.mark.parametrize(
    "paths",
    [
        ["services/S/README.md", "services/s/README.md"],
        ["deploy/S", "deploy/S/Dockerfile"],
        ["services//S/README.md"],
        ["../outside"],
        ["/absolute"],
        ["a/./b"],
    ],
)
def test_the_bundle_writer_refuses_paths_that_meet_on_disk(paths, tmp_path: Path) -> None:
    from spl.generators.bundle.writer import write_bundle

    with pytest.raises(BundlePathClash):
        write_bundle({path: b"x" for path in paths}, tmp_path / "out")
    assert not (tmp_path / "out").exists() and list(tmp_path.iterdir()) == []


def test_a_generator_writing_a_path_twice_stops_the_bundle(monkeypatch) -> None:
    """Planted: the service generator made to name both stores alike again."""
    from spl.generators import store_contract
    from spl.generators.service import generator as service

    real = store_contract.store_context

    def same_folder(store, product):  # type: ignore[no-untyped-def]
        return {**real(store, product), "name": "PositionStore"}

    monkeypatch.setattr(service, "store_context", same_folder)
    with pytest.raises(BundlePathClash, match="services/PositionStore/"):
        service.generate(_two_clouds_product())


def _two_clouds_product():  # type: ignore[no-untyped-def]
    from spl.dsl.tsm import language as tsm_language
    from spl.resolver.architecture.product import ResolvedProduct

    text = (
        "system Names\n"
        + TYPES
        + cloud("FieldCloud", ("PositionStore", 5))
        + cloud("LabCloud", ("PositionStore", 2))
    )
    return ResolvedProduct("two", tsm_language.parse_text(text, "two.tsm"), ())


def test_a_refined_type_taking_a_table_name_of_its_store_is_refused(tmp_path: Path) -> None:
    """Refined type ``Raw`` of store ``S`` would be kept in ``s_raw``, the raw table."""
    types = TYPES.replace("PositionDeg", "Raw")
    folder = line(tmp_path / "raw", cloud("C", ("S", 5)).replace("PositionDeg", "Raw"), "", types)
    system = load_product_line(folder).tsm
    (problem,) = store_errors(system)
    assert problem.message == (
        "store S: refined type Raw would be kept under the database name s_raw, which the "
        "store already uses; rename the refined type"
    )
    assert problem.location is not None and problem.location.line > 0
    result = run("resolve", folder, "--features", "Base", "-o", tmp_path / "out")
    assert result.exit_code == 1 and LOCATED_ERROR.search(result.stderr), result.output
    assert not (tmp_path / "out").exists()


def test_a_store_never_takes_a_cloud_instance_s_kubernetes_name(tmp_path: Path) -> None:
    """Cloud container ``Position`` serving robot ``store`` is the Kubernetes instance
    ``position-store``: store ``PositionStore`` must not deploy under that name too."""
    clouds = (
        cloud("DataCloud", ("PositionStore", 5))
        + """cloud container Position {
    topic Gps : rover_msgs/Position name "/gps"
    node Logger {
        implementation logger/logger
        subscribes fix <- Gps
    }
}
bridge Rover.Gps -> Position.Gps
"""
    )
    robots = robot("Rover", "DataCloud.PositionStore").replace('"rover_1"', '"store"')
    files = bundle_of(line(tmp_path / "k8s", clouds, robots))
    assert "kubernetes/position-store.yaml" in files  # the instance keeps its name
    assert folders(files, "services") == ["DataCloud_PositionStore"]
    kinds: dict[tuple[str, str], str] = {}
    for path, data in files.items():
        if path.endswith(".yaml") and "kubernetes/" in path and "kustomization" not in path:
            for document in yaml.safe_load_all(data):
                key = (document["kind"], document["metadata"]["name"])
                assert key not in kinds, f"{key} in {kinds.get(key)} and {path}"
                kinds[key] = path
