"""``spl explain`` names the resolution element, its line and feature behind every element
the rewiring makes or changes (a topic made by a qualified cross-container reference, a
bridge, a client rebound by a migration), says what an interface exchanges with whom
(the product's flow table) and where a cloud node's instances run, on small lines written
here: a drone and a central cloud; a crawler whose planner can move onboard."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from spl.cli import main

SURVEY_TSM = """system Survey
robot container Drone {
    endpoint robot_id "drone_1" url "wss://x.example.org:9000/" user "u" password env "P"
    topic Images : sensor_msgs/Image name "/camera/image"
    node Camera { implementation cam/cam publishes image -> Images }
}
robot container Rover {
    endpoint robot_id "rover_1" url "wss://x.example.org:9000/" user "u" password env "P"
    topic Report : std_msgs/String name "/report"
    node Display { implementation ui/display subscribes report <- Report }
}
cloud container Central {
    topic Report : std_msgs/String name "/report"
    node ReportGenerator {
        implementation reports/generator
        subscribes video : sensor_msgs/Image
        publishes report -> Report
    }
}
bridge Central.Report -> Rover.Report
"""
SURVEY_FM = "feature model Survey\nroot Survey { optional Reports }\n"
SURVEY_RM = """resolution model Survey
tsm "s.tsm"
fm "s.fm"

when Reports selected {
    connect ReportGenerator.video to topic Drone.Images
}
"""

CRAWL_TSM = """system Crawl
robot container Crawler {
    endpoint robot_id "crawler_1" url "wss://x.example.org:9000/" user "u" password env "P"
    node Navigator { implementation nav/navigator calls plan : nav_msgs/GetPlan }
}
cloud container Edge {
    node Planner { implementation nav/planner provides plan : nav_msgs/GetPlan name "/plan" }
}
bridge Crawler.Navigator.plan -> Edge.Planner.plan
"""
CRAWL_FM = "feature model Crawl\nroot Crawl { optional Onboard }\n"
CRAWL_RM = """resolution model Crawl
tsm "s.tsm"
fm "s.fm"

when Onboard selected {
    migrate Edge.Planner to Crawler
}
"""


def line(directory: Path, tsm: str, fm: str, rm: str) -> Path:
    directory.mkdir()
    for name, text in (("s.tsm", tsm), ("s.fm", fm), ("s.rm", rm)):
        (directory / name).write_text(text, encoding="utf-8")
    return directory


def explain(directory: Path, features: str, element: str) -> list[str]:
    result = CliRunner().invoke(main, ["explain", str(directory), "--features", features, element])
    assert result.exit_code == 0, result.output
    return result.output.splitlines()


def test_a_topic_made_by_a_cross_container_reference_names_the_statement(tmp_path):
    survey = line(tmp_path / "survey", SURVEY_TSM, SURVEY_FM, SURVEY_RM)
    rm = survey / "s.rm"
    # was: "created: in Central for the migrated ReportGenerator, mirroring Drone.Images"
    # with no migration anywhere in the product
    lines = explain(survey, "Reports", "Central.Images")
    assert lines == [
        "Central.Images: topic present, /camera/image (sensor_msgs/Image)",
        "  Central.Images: created: in Central for ReportGenerator.video, mirroring "
        "Drone.Images (ROS name /camera/image), as ReportGenerator.video is connected to "
        f"Drone.Images of container Drone by 'when Reports selected' ({rm}:5:1) ({rm}:6:5)",
    ]
    bridge = explain(survey, "Reports", "Central.endpoint.pub_Images")
    assert bridge[1].startswith(
        "  Drone.Images: bridged: to Central.Images through the endpoints, carrying "
        "Camera.image -> ReportGenerator.video, as ReportGenerator.video is connected"
    )
    assert bridge[2] == (
        "  carries Drone.Camera.image -> Central.ReportGenerator.video via "
        "Drone.Images -> Central.Images"
    )
    assert explain(survey, "Reports", "ReportGenerator.video")[-1] == (
        "  fed by Drone.Camera.image through Drone -> Central"
    )


def test_a_client_rebound_by_a_migration_names_the_migration(tmp_path):
    crawl = line(tmp_path / "crawl", CRAWL_TSM, CRAWL_FM, CRAWL_RM)
    rm = crawl / "s.rm"
    # was: "nothing in this product decided about it: as the template writes it"
    lines = explain(crawl, "Onboard", "Navigator.plan")
    assert lines[:2] == [
        "Navigator.plan: calls Planner.plan",
        "  Navigator.plan: rebound: to Planner.plan, served in its own container Crawler now "
        "(the template reached it through the endpoints), as Planner is migrated to Crawler "
        f"by 'when Onboard selected' ({rm}:5:1) ({rm}:6:5)",
    ]
    assert lines[2].startswith("  answered by Crawler.Planner.plan in Crawler; Planner: migrated")
    # without the migration the template's bridge stands, and explain says so
    assert explain(crawl, "Crawl", "Navigator.plan") == [
        "Navigator.plan: calls Crawler.endpoint.srv_Planner_plan",
        f"  nothing in this product decided about it: as the template writes it "
        f"({crawl / 's.tsm'}:4:57)",
        "  answered by Edge.Planner.plan through Crawler -> Edge",
    ]


def test_a_private_cloud_node_is_explained_by_its_instance_per_robot(tmp_path):
    survey = line(tmp_path / "survey", SURVEY_TSM, SURVEY_FM, SURVEY_RM)
    # was an instance for each robot; the rover feeds the generator nothing, and the
    # generator's instance for the rover would get none of the drone's images, so the
    # rover gets none (docs/deployment.md, "Private instances")
    assert explain(survey, "Reports", "ReportGenerator")[-3:] == [
        "  deployed private: one per robot that feeds it or that it feeds",
        "  instance Central_drone_1 for robot drone_1: drone_1 feeds it: "
        "drone_1.Camera.image -> Central_drone_1.ReportGenerator.video",
        "  no instance for robot rover_1 (not run in Central_rover_1): nothing feeds it in "
        "rover_1's deployment (fed only by drone_1.Camera.image of another robot, whose data "
        "a private instance never takes), so it has nothing to send either",
    ]


def test_a_topic_pruned_by_a_migration_is_named_by_its_container(tmp_path):
    tsm = CRAWL_TSM.replace(
        "cloud container Edge {\n",
        'cloud container Edge {\n    topic Plans : nav_msgs/Path name "/plans"\n',
    ).replace('name "/plan" }', 'name "/plan" publishes plans -> Plans }')
    crawl = line(tmp_path / "crawl", tsm, CRAWL_FM, CRAWL_RM)
    # was "Edge.Plans: not in this product" and nothing else: the entry named it "Plans"
    lines = explain(crawl, "Onboard", "Edge.Plans")
    assert lines[0] == "Edge.Plans: not in this product"
    assert lines[1].startswith(
        "  Edge.Plans: removed: no node or endpoint of the product uses this topic"
    )
