"""SPL047 (a shared cloud instance robots of two Rapyuta users use) reads the shared
instances without deciding which private instances exist, which is costly (their flows):
the shared instances are the same as those the whole placement lists, on random lines
of every sharing mode (support/random_lines.py), on the shipped lines, and where a
private instance takes a shared one's tag (a robot_id equal to a cloud's group), which
then hides the shared one as the whole placement lists it; the warning is given as
the whole placement has it."""

from __future__ import annotations

import tempfile
from pathlib import Path

from hypothesis import given, settings

from spl.core.diagnostics import ModelError
from spl.resolver.architecture.checks import _shared_instances, shared_across_users
from spl.resolver.architecture.placement import Instance, Placement
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import ProductLine, load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

from support.hypothesis_budget import examples
from support.random_lines import fleet_specs, write_line

ROOT = Path(__file__).resolve().parents[2]


def shared(instances: list[Instance]) -> list[tuple]:
    return [
        (i.place, i.container.name, tuple(n.name for n in i.nodes), i.robots)
        for i in instances
        if i.place.shared
    ]


def compare(line: ProductLine, limit: int) -> int:
    """Compares the two listings on the line's first products; how many had instances."""
    listed = 0
    for features in sorted(",".join(sorted(p)) for p in line.formula.products())[:limit]:
        try:
            system = resolve(line, selection_from_list(features)).product.system
        except ModelError:
            continue
        whole = Placement(system, []).cloud_instances()
        assert shared(_shared_instances(Placement(system, []))) == shared(whole), features
        listed += bool(whole)
    return listed


@settings(max_examples=examples(40), deadline=None)
@given(fleet_specs())
def test_random_lines_list_the_same_shared_instances(spec) -> None:  # type: ignore[no-untyped-def]
    with tempfile.TemporaryDirectory() as tmp:
        compare(load_product_line(write_line(spec, Path(tmp))), limit=8)


def test_shipped_lines_list_the_same_shared_instances() -> None:
    lines = sorted(p for p in (ROOT / "product_lines").iterdir() if p.is_dir())
    assert sum(compare(load_product_line(folder), limit=40) for folder in lines) > 0


TSM = """system Tags

robot container Rover {
    endpoint robot_id "crew" url "wss://cloud.example.org:9000/" user "alice" password env "P"
    topic Scan : sensor_msgs/LaserScan
    node Lidar {
        implementation pkg/lidar
        publishes scan -> Scan
    }
}

robot container Drone {
    endpoint robot_id "drone" url "wss://cloud.example.org:9000/" user "bob" password env "P"
    topic Scan : sensor_msgs/LaserScan
    node Camera {
        implementation pkg/camera
        publishes scan -> Scan
    }
}

cloud container Cloud group "crew" {
    topic Scan : sensor_msgs/LaserScan
    node Filter sharing private {
        implementation pkg/filter
        subscribes scan <- Scan
    }
    node Mapper sharing protected {
        implementation pkg/mapper
        subscribes scan <- Scan
    }
}

bridge Rover.Scan -> Cloud.Scan
bridge Drone.Scan -> Cloud.Scan
"""


def test_a_private_instance_taking_a_shared_ones_tag_hides_it_as_before(tmp_path: Path) -> None:
    """Rover's private instance of Cloud is Cloud_crew, the tag of the crew's protected
    instance too: the whole placement lists the private one under that tag, and no
    SPL047 is given for the protected one, which robots of alice and bob use."""
    (tmp_path / "tags.tsm").write_text(TSM, encoding="utf-8")
    (tmp_path / "tags.fm").write_text("feature model Tags\n\nroot Root {\n}\n", encoding="utf-8")
    (tmp_path / "tags.rm").write_text(
        'resolution model Tags\ntsm "tags.tsm"\nfm "tags.fm"\n', encoding="utf-8"
    )
    line = load_product_line(tmp_path)
    assert compare(line, limit=1) == 1
    system = resolve(line, selection_from_list("Root")).product.system
    tags = [i.place.tag for i in Placement(system, []).cloud_instances()]
    assert tags.count("Cloud_crew") == 1  # one tag, two instances: the private one listed
    assert shared_across_users(system) == []
