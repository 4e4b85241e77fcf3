"""What the ROS 1 and ROS 2 launch files share: XML writing, the shipped XSDs, ROS 2 launch
XML of a container."""
