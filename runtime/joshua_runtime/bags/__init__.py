"""ROS bags: rosbag2-compatible MCAP files of topics recorded as they are (serialized CDR)."""
