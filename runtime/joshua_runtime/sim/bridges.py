"""ROS side of each simulated hardware node: the same topics, message types and QoS as the real node.

One bridge per replaced node, built from that node's own settings dict:
- ENCODER_PUBLISHER: JointState of `joint_names` on `topic` at `rate_hz`.
- OPERATIONAL_LIMIT_CALIBRATION: the ranges a full sweep of the simulated arm would record, as the
  real node publishes them (`<joint>.range_min` / `.range_max`, raw ticks with the middle of each
  range at 2047) at `rate_hz`. No calibration file is written: the model knows its limits.
- ACTUATOR_SUBSCRIBER: JointState commands from `topic` become position-actuator goals; present
  states go to `state_topic` at `rate_hz` when one is set. Preset commands on `<topic>/preset` move
  to poses as the real node does; `torque_off` (the e-stop) holds the present pose and ignores goals
  until `torque_on`, as a simulated position actuator cannot go limp. With a JointTrajectory topic,
  action chunks are followed as the real node follows them (nodes/trajectory_follower.py), every 1/rate_hz.
- CAMERA_PUBLISHER: rendered frames at `width` x `height`, `rate_hz`; Image with encoding rgb8
  (MuJoCo renders RGB), or CompressedImage (JPEG) when the topic's type says so.
- LIDAR_PUBLISHER: LaserScan of 360 rays at `rate_hz` (LDS-01 geometry, see sim/lidar.py).
Joint units are those of the real drivers: radians, rad/s, and effort as a signed fraction of the
actuator's force limit. Header stamps are the ROS clock (wall time), frame_id the node's frame_id.
"""

import array
import importlib
import math

import cv2
import numpy as np
from sensor_msgs.msg import CompressedImage, Image, JointState, LaserScan
from std_msgs.msg import String

from joshua_core.node_types import spec
from joshua_core.servo_topics import FIXED_QOS, TORQUE_OFF, TORQUE_ON, preset_topic
from joshua_core.settings import NodeSettings, QosSettings
from joshua_runtime import presets
from joshua_runtime.convert.point_cloud import POINT_CLOUD2, laser_scan_to_point_cloud2
from joshua_runtime.drivers.calibration import HALF_TURN_TICKS, RADIANS_PER_TICK
from joshua_runtime.errors import SettingsError
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.operational_limit_calibration import RANGE_MAX_SUFFIX, RANGE_MIN_SUFFIX
from joshua_runtime.nodes.trajectory_follower import ChunkCommands, is_trajectory
from joshua_runtime.qos import qos_profile
from joshua_runtime.sim import lidar
from joshua_runtime.sim.cameras import CameraStream
from joshua_runtime.sim.engine import JointGroup, SimulationEngine
from joshua_runtime.sim.model import camera_id

IMAGE_ENCODING = "rgb8"
JPEG_FORMAT = "rgb8; jpeg compressed bgr8"
JPEG_QUALITY = 90


class JointStateSource:
    """Turns a JointGroup reading into JointState messages (real-driver units)."""

    def __init__(self, node, engine: SimulationEngine, group: JointGroup, frame_id: str):
        self.node, self.engine, self.group, self.frame_id = node, engine, group, frame_id
        limits = np.array(
            [
                abs(engine.model.actuator_forcerange[a, 1]) if a >= 0 and engine.model.actuator_forcelimited[a] else 0.0
                for a in group.actuators
            ]
        )
        self._effort_scale = np.where(limits > 0, 1.0 / np.where(limits > 0, limits, 1.0), 1.0)

    def message(self) -> JointState:
        reading = self.engine.read(self.group)
        msg = JointState()
        msg.header.stamp = self.node.stamp()
        msg.header.frame_id = self.frame_id
        msg.name = list(self.group.names)
        msg.position = array.array("d", reading.positions.tobytes())
        msg.velocity = array.array("d", reading.velocities.tobytes())
        msg.effort = array.array("d", (reading.efforts * self._effort_scale).tobytes())
        return msg


class EncoderBridge:
    """Publishes present joint states like ENCODER_PUBLISHER."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        group = engine.joints(settings_checks.joints(settings)[1])
        self.source = JointStateSource(node, engine, group, settings.frame_id)
        self.publisher = node.publisher(settings_checks.topic(settings))
        self.timer = node.ros.create_timer(settings_checks.period_s(settings), self.publish)

    def publish(self) -> None:
        self.publisher.publish(self.source.message())


class CalibrationBridge:
    """Publishes the model's joint ranges like OPERATIONAL_LIMIT_CALIBRATION after a full sweep."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        self.node, self.frame_id = node, settings.frame_id
        names = settings_checks.joints(settings)[1]
        engine.joints(names)  # every name must be a joint of the model
        self.names, self.limits = [], []
        for name in names:
            low, high = engine.model.joint(name).range
            self.names += [name + RANGE_MIN_SUFFIX, name + RANGE_MAX_SUFFIX]
            self.limits += [
                float(round(HALF_TURN_TICKS + low / RADIANS_PER_TICK)),
                float(round(HALF_TURN_TICKS + high / RADIANS_PER_TICK)),
            ]
        self.publisher = node.publisher(settings_checks.topic(settings))
        self.timer = node.ros.create_timer(settings_checks.period_s(settings), self.publish)
        if settings.calibration_file:
            node.log.info(f"{settings.name}: simulated, {settings.calibration_file} is left as it is")

    def publish(self) -> None:
        msg = JointState(name=self.names, position=self.limits)
        msg.header.stamp = self.node.stamp()
        msg.header.frame_id = self.frame_id
        self.publisher.publish(msg)


class ActuatorBridge:
    """Applies JointState commands to position actuators like ACTUATOR_SUBSCRIBER."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        self.engine = engine
        self.group = engine.joints(settings_checks.joints(settings)[1], actuated=True)
        self._index = {name: i for i, name in enumerate(self.group.names)}
        topic = settings_checks.topic(settings)
        if is_trajectory(topic):
            period = settings_checks.period_s(settings)
            self.chunks = ChunkCommands(node, topic, list(self.group.names), period, self.on_goals)
        else:
            self.subscription = node.subscription(topic, self.on_command)
        self.poses = presets.poses({p.name: dict(p.positions) for p in settings.preset})
        self.frozen = False  # after torque_off, until torque_on
        self.presets = node.ros.create_subscription(
            String, preset_topic(topic.name), self.on_preset, qos_profile(QosSettings(**FIXED_QOS))
        )
        self.state_publisher = None
        if settings.HasField("state_topic"):
            self.source = JointStateSource(node, engine, self.group, settings.frame_id)
            self.state_publisher = node.publisher(settings.state_topic)
            self.timer = node.ros.create_timer(settings_checks.period_s(settings), self.publish_state)

    def goals(self, msg: JointState) -> np.ndarray:
        """Goal per joint of the group: matched by name, else by order when the lengths agree; NaN = keep."""
        goals = np.full(len(self.group.names), math.nan)
        positions = list(msg.position)
        if msg.name:
            for name, value in zip(msg.name, positions):
                i = self._index.get(name)
                if i is not None:
                    goals[i] = value
        elif len(positions) == len(goals):
            goals[:] = positions
        return goals

    def on_command(self, msg: JointState) -> None:
        self.on_goals(self.goals(msg))

    def on_goals(self, goals: np.ndarray) -> None:
        if not self.frozen:
            self.engine.command(self.group, goals)

    def on_preset(self, msg: String) -> None:
        action = presets.expand(msg.data.strip(), self.poses, list(self.group.names))
        if action is None:
            return
        if TORQUE_OFF in action.preset_commands:
            self.frozen = True
            self.engine.command(self.group, self.engine.read(self.group).positions)
        elif TORQUE_ON in action.preset_commands:
            self.frozen = False
        elif not self.frozen:
            self.engine.command(self.group, np.array(action.position, dtype=float))

    def publish_state(self) -> None:
        self.state_publisher.publish(self.source.message())


class CameraBridge:
    """Publishes rendered frames like CAMERA_PUBLISHER; `stream` is handed to the CameraThread."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        self.node = node
        self.name = settings.name
        self.frame_id = settings.frame_id
        width, height = settings_checks.image_size(settings)
        topic = settings_checks.topic(settings)
        self.compressed = topic.message_type.endswith("/CompressedImage")
        self.publisher = node.publisher(topic)
        camera = _camera_for(engine, self.frame_id, node.default_camera)
        self.stream = CameraStream(camera, width, height, 1.0 / settings_checks.period_s(settings), self.publish)

    def publish(self, pixels: np.ndarray, _sim_time: float) -> None:
        if self.compressed:
            msg = CompressedImage()
            msg.format = JPEG_FORMAT
            ok, encoded = cv2.imencode(
                ".jpg", cv2.cvtColor(pixels, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY]
            )
            if not ok:
                return
            msg.data = array.array("B", encoded.tobytes())
        else:
            msg = Image()
            msg.height, msg.width = pixels.shape[0], pixels.shape[1]
            msg.encoding = IMAGE_ENCODING
            msg.is_bigendian = 0
            msg.step = pixels.shape[1] * 3
            msg.data = array.array("B", pixels.tobytes())
        msg.header.stamp = self.node.stamp()
        msg.header.frame_id = self.frame_id
        self.publisher.publish(msg)


class LidarBridge:
    """Publishes ray-cast scans like LIDAR_PUBLISHER (as PointCloud2 when the topic's type says so)."""

    def __init__(self, node, engine: SimulationEngine, settings: NodeSettings):
        self.node, self.engine = node, engine
        self.frame_id = settings.frame_id
        self.sensor = lidar.PlanarLidar(engine.model, lidar.lidar_site(engine.model, self.frame_id))
        self.publisher = node.publisher(settings_checks.topic(settings))
        self.as_cloud = settings_checks.topic(settings).message_type == POINT_CLOUD2
        self.timer = node.ros.create_timer(settings_checks.period_s(settings), self.publish)

    def message(self) -> LaserScan:
        with self.engine.lock:
            ranges = self.sensor.scan(self.engine.data)
        msg = LaserScan()
        msg.header.stamp = self.node.stamp()
        msg.header.frame_id = self.frame_id
        msg.angle_min, msg.angle_max, msg.angle_increment = lidar.ANGLE_MIN, lidar.ANGLE_MAX, lidar.ANGLE_INCREMENT
        msg.time_increment, msg.scan_time = lidar.TIME_INCREMENT_S, lidar.SCAN_TIME_S
        msg.range_min, msg.range_max = lidar.RANGE_MIN_M, lidar.RANGE_MAX_M
        msg.ranges = array.array("f", ranges.astype(np.float32).tobytes())
        msg.intensities = array.array("f", self.sensor.intensities(ranges).astype(np.float32).tobytes())
        return msg

    def publish(self) -> None:
        scan = self.message()
        self.publisher.publish(laser_scan_to_point_cloud2(scan) if self.as_cloud else scan)


def _camera_for(engine: SimulationEngine, frame_id: str, default_camera: str) -> int:
    """The model camera named like the node's frame_id, else the simulation's camera setting."""
    model = engine.model
    if frame_id and any(model.camera(c).name == frame_id for c in range(model.ncam)):
        return camera_id(model, frame_id)
    return camera_id(model, default_camera)


def make_bridge(node, engine: SimulationEngine, settings: NodeSettings):
    """The bridge that stands in for one hardware node (named by the node-type registry), from its settings."""
    entry = spec(settings.type)
    if entry is None or not entry.sim_bridge:
        raise SettingsError(f"{settings.name}: node type {settings.type} cannot be simulated")
    module_name, class_name = entry.sim_bridge.split(":")
    bridge = getattr(importlib.import_module(module_name), class_name)
    return bridge(node, engine, settings)
