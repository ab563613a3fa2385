"""The Foxglove bridge: the robot's ROS topics served over the Foxglove WebSocket protocol."""
