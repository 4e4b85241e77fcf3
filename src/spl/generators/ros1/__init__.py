"""The ros1 target: roslaunch XML files (docs/outputs.md)."""
