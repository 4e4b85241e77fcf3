"""The shipped XSDs accept real launch files and refuse broken ones."""

from __future__ import annotations

import pytest

from spl.generators.launch.launch_schema import validate_ros1_launch, validate_ros2_launch

ROS1_FULL = b"""<?xml version="1.0"?>
<launch>
  <arg name="robot" default="youbot" doc="which base"/>
  <machine name="pc" address="10.0.0.2" env-loader="/opt/ros/env.sh" user="ros"/>
  <param name="/use_sim_time" value="false" type="bool"/>
  <rosparam command="load" file="$(find mapping)/config/map.yaml"/>
  <env name="ROSCONSOLE_FORMAT" value="${message}"/>
  <group ns="$(arg robot)" if="true">
    <remap from="scan" to="base_scan"/>
    <node pkg="map_server" type="map_server" name="map" args="map.yaml" respawn="true"
          output="screen" launch-prefix="nice">
      <param name="frame_id" value="map"/>
      <rosparam param="limits">{a: 1}</rosparam>
      <remap from="map" to="/map"/>
      <env name="X" value="1"/>
    </node>
  </group>
  <include file="$(find youbot)/launch/base.launch" ns="base" pass_all_args="true">
    <arg name="rate" value="10"/>
  </include>
  <test test-name="map_test" pkg="map_server" type="test_map" time-limit="60"/>
</launch>
"""

ROS2_FULL = b"""<launch>
  <arg name="robot" default="youbot" description="which base">
    <choice value="youbot"/>
    <choice value="roomba"/>
  </arg>
  <let name="rate" value="10"/>
  <set_env name="RCUTILS_COLORIZED_OUTPUT" value="1"/>
  <group scoped="true">
    <push-ros-namespace namespace="$(var robot)"/>
    <node pkg="demo_nodes_cpp" exec="talker" name="talker" namespace="chat" output="screen"
          respawn="true" ros_args="--log-level debug" if="$(var use_talker)">
      <param name="rate" value="$(var rate)" type="int"/>
      <param from="$(find-pkg-share demo)/params.yaml"/>
      <param name="limits">
        <param name="max" value="1.0"/>
      </param>
      <remap from="chatter" to="/chat"/>
      <env name="X" value="1"/>
    </node>
  </group>
  <executable cmd="ls -l" cwd="/tmp" name="lister" output="log"/>
  <include file="$(find-pkg-share demo)/launch/other.launch.xml">
    <arg name="rate" value="5"/>
  </include>
  <timer period="2.0">
    <node pkg="demo_nodes_cpp" exec="listener"/>
  </timer>
</launch>
"""


def test_documented_examples_are_valid():
    assert validate_ros1_launch(ROS1_FULL) == []
    assert validate_ros2_launch(ROS2_FULL) == []


@pytest.mark.parametrize(
    ("document", "expected"),
    [
        (b'<launch><node type="t" name="n"/></launch>', "'pkg' is required"),
        (b'<launch><node pkg="p" name="n"/></launch>', "'type' is required"),
        (
            b'<launch><node pkg="p" type="t"><param name="x" value="1" type="float"/></node>'
            b"</launch>",
            "float",
        ),
        (b'<launch><remap from="a"/></launch>', "'to' is required"),
        (b'<launch><node pkg="p" type="t" colour="red"/></launch>', "colour"),
        (b'<launch><nodes pkg="p" type="t"/></launch>', "nodes"),
        (b'<launch><rosparam command="upload">a: 1</rosparam></launch>', "upload"),
        (b'<node pkg="p" type="t"/>', "expected <launch>"),
        (b"<launch><node pkg='p'></launch>", "not well-formed"),
    ],
)
def test_ros1_schema_refuses(document, expected):
    problems = validate_ros1_launch(document)
    assert problems and any(expected in p for p in problems), problems


@pytest.mark.parametrize(
    ("document", "expected"),
    [
        (b'<launch><node pkg="p" name="n"/></launch>', "'exec' is required"),
        (b'<launch><node exec="e" type="t" pkg="p"/></launch>', "type"),
        (
            b'<launch><node pkg="p" exec="e"><param name="x" value="1" type="double"/></node>'
            b"</launch>",
            "double",
        ),
        (b'<launch><node pkg="p" exec="e" ns="/a"/></launch>', "ns"),
        (b'<launch><rosparam param="a">1</rosparam></launch>', "rosparam"),
        (b'<launch><let name="a"/></launch>', "'value' is required"),
    ],
)
def test_ros2_schema_refuses(document, expected):
    problems = validate_ros2_launch(document)
    assert problems and any(expected in p for p in problems), problems


def test_problems_carry_line_numbers():
    (problem,) = validate_ros1_launch(b'<launch>\n\n  <node type="t"/>\n</launch>')
    assert problem.startswith("3:")
