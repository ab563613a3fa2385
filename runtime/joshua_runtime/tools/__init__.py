"""Command-line tools for a running robot: ROS topics (joshua-topic)."""
