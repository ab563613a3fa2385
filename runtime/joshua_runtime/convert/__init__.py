"""Conversions between driver packets and ROS messages: joint_state.py, image.py, laser_scan.py."""
