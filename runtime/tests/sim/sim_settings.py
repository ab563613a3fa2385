"""Settings of the SIMULATION process, compiled by joshuac from an SO-100 description in MODE_SIMULATION.

Each hardware node is a `node { }` block of the description; `simulation(...)` puts the chosen ones
in a robot and returns the settings of the engine that stands in for them.
"""

from joshua_core import so100
from testsupport.compiled_settings import compiled_settings

SO100_JOINTS = list(so100.SO100_JOINTS)
SO100_RANGES = so100.SO100_RANGES

ENCODER = """
  node {
    name: "arm_encoder"
    type: ENCODER_PUBLISHER
    topic_name: "/arm/joint_states"
    serial_port: "/dev/ttyACM0"
    rate_hz: 100
  }
"""
CALIBRATION = """
  node {
    name: "arm_calibration"
    type: OPERATIONAL_LIMIT_CALIBRATION
    topic_name: "/arm/limits"
    serial_port: "/dev/ttyACM0"
    device_ids: [1, 6]
    joint_names: ["shoulder_pan", "gripper"]
    rate_hz: 10
    calibration_file: "arm.json"
  }
"""
ACTUATOR = """
  node {
    name: "arm_actuator"
    type: ACTUATOR_SUBSCRIBER
    topic_name: "/arm/command"
    state_topic: "/arm/present"
    serial_port: "/dev/ttyACM1"
    rate_hz: 50
  }
"""
# The same actuator commanded by action chunks.
CHUNK_ACTUATOR = ACTUATOR.replace(
    'topic_name: "/arm/command"',
    'topic_name: "/arm/chunks" message_type: "trajectory_msgs/msg/JointTrajectory"',
)
CAMERA = """
  node {
    name: "front_camera"
    type: CAMERA_PUBLISHER
    topic_name: "/camera/image_raw"
    camera_index: 0
    width: 320
    height: 240
    rate_hz: 10
    frame_id: "camera"
  }
"""
# A second camera, JPEG-compressed, whose frame_id names the model's wrist camera.
WRIST_CAMERA = """
  node {
    name: "wrist_camera"
    type: CAMERA_PUBLISHER
    topic_name: "/wrist/image/compressed"
    message_type: "sensor_msgs/msg/CompressedImage"
    camera_index: 1
    width: 160
    height: 120
    rate_hz: 5
    frame_id: "wrist"
  }
"""
LIDAR = """
  node {
    name: "lidar"
    type: LIDAR_PUBLISHER
    topic_name: "/scan"
    serial_port: "/dev/ttyUSB0"
    baud_rate: 230400
    rate_hz: 5
    frame_id: "laser"
  }
"""


def simulation(*nodes: str, overrides=()) -> dict:
    """The settings of the SIMULATION process of a robot made of the `node { }` blocks given."""
    text = (
        'robot_config {\n  name: "sim_test"\n  mode: MODE_SIMULATION\n'
        '  simulation { model: "builtin:so100" }\n' + "".join(nodes) + "}\n"
    )
    return compiled_settings(text, overrides)["simulation"]
