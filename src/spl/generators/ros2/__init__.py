"""The ros2 target: ROS 2 launch XML files (docs/outputs.md)."""
