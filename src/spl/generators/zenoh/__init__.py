"""The zenoh target: zenoh-bridge-ros2dds configurations (docs/deployment.md)."""
