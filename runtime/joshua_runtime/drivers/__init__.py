"""ROS-free hardware drivers that speak PerceptionPacket / ActionPacket."""
