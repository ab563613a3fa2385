"""Settings dicts shaped like joshuac's, for a simulated SO-100 with encoder, actuator, camera and lidar."""

SO100_JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]
# spec/protocols.md section 3.
SO100_RANGES = {
    "shoulder_pan": (-1.92, 1.92),
    "shoulder_lift": (-1.75, 1.75),
    "elbow_flex": (-1.69, 1.69),
    "wrist_flex": (-1.66, 1.66),
    "wrist_roll": (-2.74, 2.74),
    "gripper": (-0.17, 1.75),
}
DEFAULT_QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}
SENSOR_QOS = {"history": "KEEP_LAST", "depth": 5, "reliability": "BEST_EFFORT", "durability": "VOLATILE"}


def _topic(name: str, message_type: str, qos: dict) -> dict:
    return {"name": name, "message_type": message_type, "qos": dict(qos)}


def node_settings(name: str, node_type: str, **fields) -> dict:
    """One node's settings with every key of the entrypoint contract."""
    settings = {
        "robot": "sim_test", "mode": "MODE_SIMULATION", "name": name, "type": node_type,
        "topic": None, "state_topic": None, "inputs": [], "qos": dict(DEFAULT_QOS),
        "serial_port": "", "baud_rate": 0, "device_ids": [], "joint_names": [], "calibration_file": "",
        "camera_index": -1, "video_source": "", "width": 640, "height": 480, "rate_hz": 100.0,
        "frame_id": "base_link", "model_path": "", "policy_type": "", "device": "cpu",
        "output_format": "lerobot", "output_directory": "", "simulation": None,
    }
    settings.update(fields)
    return settings


def encoder(rate_hz: float = 100.0) -> dict:
    return node_settings(
        "arm_encoder", "ENCODER_PUBLISHER", topic=_topic("/arm/joint_states", "sensor_msgs/msg/JointState", DEFAULT_QOS),
        serial_port="/dev/ttyACM0", baud_rate=1_000_000, device_ids=[1, 2, 3, 4, 5, 6],
        joint_names=list(SO100_JOINTS), rate_hz=rate_hz,
    )


def calibration() -> dict:
    return node_settings(
        "arm_calibration", "OPERATIONAL_LIMIT_CALIBRATION",
        topic=_topic("/arm/limits", "sensor_msgs/msg/JointState", DEFAULT_QOS), serial_port="/dev/ttyACM0",
        baud_rate=1_000_000, device_ids=[1, 6], joint_names=["shoulder_pan", "gripper"], rate_hz=10.0,
        calibration_file="arm.json",
    )


def actuator(state_topic: bool = True) -> dict:
    return node_settings(
        "arm_actuator", "ACTUATOR_SUBSCRIBER", topic=_topic("/arm/command", "sensor_msgs/msg/JointState", DEFAULT_QOS),
        state_topic=_topic("/arm/present", "sensor_msgs/msg/JointState", DEFAULT_QOS) if state_topic else None,
        serial_port="/dev/ttyACM1", baud_rate=1_000_000, device_ids=[1, 2, 3, 4, 5, 6],
        joint_names=list(SO100_JOINTS), rate_hz=50.0,
    )


def camera(width: int = 320, height: int = 240, rate_hz: float = 10.0) -> dict:
    return node_settings(
        "front_camera", "CAMERA_PUBLISHER", topic=_topic("/camera/image_raw", "sensor_msgs/msg/Image", SENSOR_QOS),
        qos=dict(SENSOR_QOS), camera_index=0, width=width, height=height, rate_hz=rate_hz, frame_id="camera",
    )


def wrist_camera() -> dict:
    """A second camera, JPEG-compressed, whose frame_id names the model's wrist camera."""
    return node_settings(
        "wrist_camera", "CAMERA_PUBLISHER",
        topic=_topic("/wrist/image/compressed", "sensor_msgs/msg/CompressedImage", SENSOR_QOS),
        qos=dict(SENSOR_QOS), camera_index=1, width=160, height=120, rate_hz=5.0, frame_id="wrist",
    )


def lidar() -> dict:
    return node_settings(
        "lidar", "LIDAR_PUBLISHER", topic=_topic("/scan", "sensor_msgs/msg/LaserScan", SENSOR_QOS),
        qos=dict(SENSOR_QOS), serial_port="/dev/ttyUSB0", baud_rate=230_400, rate_hz=5.0, frame_id="laser",
    )


def simulation(simulates: list[dict], model: str = "builtin:so100", realtime_factor: float = 1.0,
               timestep_s: float | None = None, camera_name: str = "", gl_backend: str = "egl") -> dict:
    """The settings of the SIMULATION process that replaces `simulates`."""
    return node_settings(
        "simulation", "SIMULATION",
        simulation={"model": model, "timestep_s": timestep_s, "realtime_factor": realtime_factor,
                    "camera": camera_name, "gl_backend": gl_backend, "simulates": simulates},
    )
