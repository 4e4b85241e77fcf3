"""``spl import launch`` on small launch files written here: what varies becomes
features, optional nodes and statements that round-trip through roslaunch's own loader;
what cannot be carried over is a located warning; hostile input is refused in one line,
exit 1, before anything is written; without ROS it says so in one line.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest

from spl.pipeline import check_models

from support.launch_round_trip import (
    differences,
    import_launch,
    load_with_roslaunch,
    product_launch_files,
    stub_packages,
)

VARIANTS = """<launch>
  <arg name="a" default="x"/>
  <arg name="flag" default="false"/>
  <node pkg="demo" type="always" name="always">
    <param name="i" value="7"/>
    <param name="tiny" type="double" value="1e-05"/>
    <param name="auto_text" value="1e-05"/>
    <param name="on" value="true"/>
    <param name="text" type="str" value="007"/>
    <param name="by_a" value="$(arg a)"/>
    <rosparam>{list: [1, 2.5, "x"], nested: {deep: {v: -3, w: 1.0e+20}}, dollar: "$(b)"}</rosparam>
    <rosparam param="mixed" subst_value="true">$(eval 1 if a == 'x' else 'one')</rosparam>
  </node>
  <group if="$(eval a == 'y' and flag)">
    <node pkg="demo" type="joint" name="joint"/>
  </group>
  <group unless="$(arg flag)">
    <node pkg="demo" type="off" name="off" ns="side/deeper">
      <param name="p" value="$(arg a)"/>
    </node>
  </group>
  <node pkg="$(arg a)_pkg" type="impl" name="impl"/>
  <node pkg="demo" type="r" name="r" args="--verbose">
    <remap from="in" to="/x/in"/><remap from="out" to="y"/>
  </node>
</launch>
"""


@pytest.fixture
def package_path(tmp_path: Path) -> Path:
    """A package path with one package, ``demo``, and its ``launch/`` folder."""
    root = stub_packages(tmp_path / "packages", "demo")
    (root / "demo" / "launch").mkdir()
    return root


def write_launch(package_path: Path, name: str, text: str) -> Path:
    path = package_path / "demo" / "launch" / name
    path.write_text(text)
    return path


def run_import(launch: Path, package_path: Path, out: Path, *options: str):
    return import_launch(str(launch), "--package-path", str(package_path), "-o", str(out), *options)


def test_variability_becomes_features_and_statements_that_round_trip(package_path, tmp_path):
    launch = write_launch(package_path, "variants.launch", VARIANTS)
    out = tmp_path / "line"
    status, stdout, stderr = run_import(launch, package_path, out, "--arg", "a=x,y",
                                        "--arg", "flag=true,false")  # fmt: skip
    assert status == 0, stderr
    assert stdout.startswith("imported variants: 4 products, 5 nodes (2 optional)")
    assert [d for d in check_models(out, count=False)[1] if d.severity == "error"] == []
    fm = (out / "variants.fm").read_text()
    assert "mandatory a xor { x y }" in fm and "optional flag" in fm
    # `joint` comes with a=y and flag together: a feature of that combination
    assert "y_true <=> y and flag" in fm
    rm = (out / "variants.rm").read_text()
    assert "when flag not selected {\n    require Cloud_side_deeper.off\n}" in rm
    assert "when y selected {\n    implementation Cloud.impl = y_pkg/impl" in rm
    assert 'parameter Cloud.always.by_a = "y"' in rm
    assert 'args "--verbose in:=/x/in out:=y"' in (out / "variants.tsm").read_text()
    jobs = []
    for a, flag in itertools.product(["x", "y"], ["true", "false"]):
        product = out / "products" / f"{a}_{flag}.yaml"
        generated = product_launch_files(out, product, tmp_path / f"{a}_{flag}")
        jobs += [{"files": [str(launch)], "args": {"a": a, "flag": flag}},
                 {"files": [str(f) for f in generated]}]  # fmt: skip
    loaded = load_with_roslaunch(jobs, [package_path])
    for original, imported in zip(loaded[::2], loaded[1::2], strict=True):
        assert differences(original, imported) == set()
        assert original["nodes"], "the comparison compared something"
    assert {"/always/tiny", "/always/nested/deep/w", "/always/mixed"} <= loaded[0]["params"].keys()


def test_the_same_launch_files_give_the_same_bytes(package_path, tmp_path):
    launch = write_launch(package_path, "variants.launch", VARIANTS)
    written = []
    for attempt in ("one", "two"):
        out = tmp_path / attempt
        status, _, stderr = run_import(launch, package_path, out, "--arg", "a=x,y")
        assert status == 0, stderr
        written.append({p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()})
    assert written[0] == written[1]
    assert len(written[0]) == 6  # .tsm .fm .rm, two products, the report


def test_what_is_not_carried_over_is_a_located_warning_and_no_command_runs(package_path, tmp_path):
    marker = tmp_path / "ran"
    launch = write_launch(package_path, "warn.launch", f"""<launch>
  <test test-name="t" pkg="demo" type="t"/>
  <param name="cmd" command="touch {marker}"/>
  <node pkg="demo" type="t" name="e" args="$(eval undefined_name + 1)"/>
  <node pkg="demo" type="t" name="f" args="$(find missing_pkg)/x"/>
  <node pkg="demo" type="t" name="g" respawn="true"><env name="A" value="1"/></node>
  <node pkg="demo" type="t" name="h"><param name="c" command="touch {marker}"/></node>
  <param name="global" value="1"/>
  <node pkg="demo" type="t" name="topic"/>
  <node pkg="Bad-Pkg" type="t" name="bad"/>
  <node pkg="demo" type="t" name="quoted" args="--title 'a b'"/>
</launch>
""")  # fmt: skip
    out = tmp_path / "line"
    status, stdout, stderr = run_import(launch, package_path, out)
    assert status == 0, stderr
    assert not marker.exists()
    expected = [
        f"{launch}:2: warning: <test test-name=\"t\"> left out: a test is not part of the",
        f"{launch}:3: warning: <param name=\"cmd\" command=...> left out: spl runs no command",
        f"{launch}:4: warning: <node name=\"e\"> left out: '$(eval undefined_name + 1)': the "
        "value of $(eval) is unknown",
        f"{launch}:5: warning: <node name=\"f\"> left out: package missing_pkg is not in the "
        "package path",
        f"{launch}:6: warning: node /g: env A=1 left out",
        f"{launch}:6: warning: node /g: respawn left out",
        f"{launch}:7: warning: <param name=\"c\" command=...> left out",
        f"{launch}:8: warning: parameter /global left out: it is private to no node",
        f"{launch}:9: warning: node /topic left out: its name is not an identifier, or a word",
        f"{launch}:10: warning: node /bad left out: 'Bad-Pkg' is not a valid ROS package name",
        f"{launch}:11: warning: node /quoted: args '--title a b' left out: an argument holds "
        "blanks",
    ]  # fmt: skip
    lines = stderr.splitlines()
    assert len(lines) == len(expected)
    for line, start in zip(lines, expected, strict=True):
        assert line.startswith(start), line
    assert (out / "import-report.txt").read_text().splitlines()[1:] == lines
    assert "3 nodes (0 optional), 11 things not carried over" in stdout


def test_the_summary_counts_one_of_each_in_the_singular(package_path, tmp_path):
    launch = write_launch(
        package_path,
        "one.launch",
        '<launch><node pkg="demo" type="t" name="t" respawn="true"/></launch>',
    )
    out = tmp_path / "line"
    status, stdout, stderr = run_import(launch, package_path, out)
    assert status == 0, stderr
    assert stdout.startswith(
        "imported one: 1 product, 1 node (0 optional), 1 thing not carried over"
    )
    assert (
        (out / "import-report.txt").read_text().startswith("spl import launch: 1 thing not carried")
    )


ALIASES = "a: &a [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"{n}: &{n} [{', '.join([f'*{p}'] * 10)}]\n" for p, n in zip("abcdefg", "bcdefgh", strict=True)
)


@pytest.mark.parametrize(
    "files, reason",
    [
        ({"bomb.launch": '<?xml version="1.0"?>\n<!DOCTYPE launch [<!ENTITY a "aaaa">'
          '<!ENTITY b "&a;&a;&a;&a;">]>\n<launch><node pkg="p" type="t" name="&b;"/></launch>'},
         "bomb.launch: a DOCTYPE or entity declaration (refused: entity expansion)"),
        ({"huge.launch": "<launch>" + "<!-- padding -->" * 70_000 + "</launch>"},
         "huge.launch is 1120017 bytes, more than 1000000"),
        ({"out.launch": '<launch><include file="{outside}/x.launch"/></launch>'},
         "x.launch is outside the package path"),
        ({"out.launch": '<launch><rosparam command="load" file="{outside}/x.yaml"/></launch>'},
         "x.yaml is outside the package path"),
        ({"cycle.launch": '<launch>\n<include file="$(find demo)/launch/cycle.launch"/></launch>'},
         "cycle.launch:2: includes nested more than 40 deep (a cycle?)"),
        ({"aliases.launch": '<launch><rosparam command="load" file="$(dirname)/a.yaml"/></launch>',
          "a.yaml": ALIASES}, "a rosparam value of more than 200000 items (YAML aliases?)"),
        ({"syntax.launch": '<launch>\n<node pkg="p" type="t" name="n"'},
         "syntax.launch:2:1: invalid launch XML: unclosed token"),
        ({"bool.launch": '<launch><arg name="a" default="maybe"/>\n<group if="$(arg a)"/>'
          "</launch>"}, "bool.launch:2: maybe is not a 'bool' type"),
        ({"unset.launch": '<launch><arg name="x"/>\n<node pkg="p" type="t" name="$(arg x)"/>'
          "</launch>"}, "unset.launch:2: <node name=\"$(arg x)\"> needs arg 'x', which is not set"),
    ],
)  # fmt: skip
def test_hostile_or_broken_input_is_refused_in_one_line_and_nothing_is_written(
    package_path, tmp_path, files, reason
):
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    (outside / "x.launch").write_text("<launch/>")
    (outside / "x.yaml").write_text("a: 1\n")
    paths = [
        write_launch(package_path, name, text.replace("{outside}", str(outside)))
        for name, text in files.items()
    ]
    out = tmp_path / "line"
    status, stdout, stderr = run_import(paths[0], package_path, out)
    assert status == 1
    assert stdout == ""
    assert len(stderr.splitlines()) == 1 and stderr.startswith("error: "), stderr
    assert reason in stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["elsewhere", "packages"]


def test_an_existing_folder_is_never_overwritten(package_path, tmp_path):
    launch = write_launch(package_path, "variants.launch", VARIANTS)
    out = tmp_path / "line"
    out.mkdir()
    (out / "mine.tsm").write_text("system Mine\n")
    status, _, stderr = run_import(launch, package_path, out)
    assert status == 1
    assert stderr == f"error: {out} exists and is not an empty folder; import into a new one\n"
    assert [p.name for p in out.iterdir()] == ["mine.tsm"]


@pytest.mark.parametrize(
    "option, message",
    [
        ("model", "--arg 'model': expected NAME=V1,V2,... with a launch arg name"),
        ("model=a,b,a", "--arg model: a value is given twice"),
        ("model=a b", "--arg model: value 'a b' is not a plain word"),
        # roslaunch ignores an argument no file declares: every product would be one
        ("modle=a,b", '--arg modle: no launch file given declares <arg name="modle">'),
    ],
)
def test_a_malformed_arg_is_refused(package_path, tmp_path, option, message):
    launch = write_launch(package_path, "variants.launch", VARIANTS)
    status, _, stderr = run_import(launch, package_path, tmp_path / "line", "--arg", option)
    assert status == 1
    assert stderr.startswith(f"error: {message}")
    assert not (tmp_path / "line").exists()


def test_without_ros_it_says_so_in_one_line(package_path, tmp_path, monkeypatch):
    launch = write_launch(package_path, "variants.launch", VARIANTS)
    monkeypatch.setenv("PATH", str(tmp_path / "no-ros-here"))
    status, _, stderr = run_import(launch, package_path, tmp_path / "line")
    assert status == 2  # a program the command cannot do without, as for spl smoke
    assert stderr == "error: roslaunch not found: apt-get install ros-core python3-roslaunch\n"
    assert not (tmp_path / "line").exists()


MACHINES = """<launch>
  <machine name="turtlebot" address="192.0.2.10" env-loader="/opt/ros/env.sh" user="pi"/>
  <node pkg="demo" type="driver" name="driver" machine="turtlebot"/>
  <node pkg="demo" type="planner" name="planner"/>
  <group ns="arm"><node pkg="demo" type="ctl" name="controller" machine="turtlebot"/></group>
</launch>
"""


def test_robot_patterns_and_machines_split_robot_and_cloud(package_path, tmp_path):
    launch = write_launch(package_path, "machines.launch", MACHINES)
    out = tmp_path / "line"
    status, _, stderr = run_import(launch, package_path, out, "--robot", "turtlebot")
    assert status == 0, stderr
    assert stderr == (
        f"{launch}:2: warning: machine turtlebot (192.0.2.10) left out: a container says "
        "where nodes run (--robot may name the machine)\n"
    )
    tsm = (out / "machines.tsm").read_text()
    robot, arm, cloud = tsm.split("container ")[1:]
    assert robot.startswith("Robot {") and "node driver" in robot and "planner" not in robot
    assert arm.startswith("Robot_arm {") and 'namespace "/arm"' in arm
    assert "node controller" in arm
    assert cloud.startswith("Cloud {") and "node planner" in cloud
    # no argument: one product, selecting the root
    assert (out / "products" / "machines.yaml").read_text() == (
        "product: machines\nfeatures: [machines]\n"
    )
    assert [d for d in check_models(out, count=False)[1] if d.severity == "error"] == []
    generated = product_launch_files(out, out / "products" / "machines.yaml", tmp_path / "b")
    original, imported = load_with_roslaunch(
        [{"files": [str(launch)]}, {"files": [str(f) for f in generated]}], [package_path]
    )
    assert differences(original, imported) == set()
    assert set(original["nodes"]) == {"/driver", "/planner", "/arm/controller"}


def test_without_robot_patterns_every_node_is_in_one_cloud_container(package_path, tmp_path):
    launch = write_launch(package_path, "machines.launch", MACHINES)
    status, _, stderr = run_import(launch, package_path, tmp_path / "line")
    assert status == 0, stderr
    tsm = (tmp_path / "line" / "machines.tsm").read_text()
    assert "robot container" not in tsm
    assert "cloud container Cloud {" in tsm and "cloud container Cloud_arm {" in tsm


def test_two_combinations_named_alike_are_refused(package_path, tmp_path):
    launch = write_launch(package_path, "two.launch", (
        '<launch><arg name="a" default="x"/><arg name="b" default="z"/></launch>'))  # fmt: skip
    out = tmp_path / "line"
    status, _, stderr = run_import(launch, package_path, out, "--arg", "a=x_y,x",
                                   "--arg", "b=z,y_z")  # fmt: skip
    assert status == 1
    assert stderr == (
        "error: the combinations x_y z and x y_z would both be the product x_y_z "
        "(values joined with _)\n"
    )
    assert not out.exists()
