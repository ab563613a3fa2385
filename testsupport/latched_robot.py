"""A mock robot whose ROBOT_STATE_PUBLISHER keeps /tf_static and /robot_description for late subscribers,
beside a recorder and a Foxglove bridge that subscribe to them too (so those topics can be discovered
through a subscription before their publisher)."""

from pathlib import Path


def latched_robot(domain: str, bags: Path, foxglove_port: int) -> str:
    return f'''robot_config {{ name: "latched" mode: MODE_TELEOPERATION ros_domain_id: {domain}
      foxglove {{ port: {foxglove_port} bind: "127.0.0.1" }}
      node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 50 }}
      node {{ name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states"
              state_topic: "/follower/joint_states" }}
      node {{ name: "camera" type: MOCK_CAMERA_PUBLISHER topic_name: "/camera/image_raw" width: 320 height: 240 }}
      node {{ name: "lidar" type: MOCK_LIDAR_PUBLISHER topic_name: "/scan" }}
      node {{ name: "state" type: ROBOT_STATE_PUBLISHER topic_name: "/follower/joint_states" }}
      node {{ name: "recorder" type: DATA_SUBSCRIBER output_format: "mcap" topic_name: "/follower/joint_states"
              output_directory: "{bags}" input_topics: ["/leader/joint_states", "/scan", "/tf"] }} }}'''
