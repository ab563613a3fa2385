"""A scripted SO-100 motion published as JointState commands, to drive the simulated arm in demos.

Run it as a CUSTOM node (or by hand) next to a MODE_SIMULATION robot, on the actuator's topic_name:

    python -m joshua_runtime.sim.scripted_motion --topic /so100/command [--rate-hz 50]

It loops through KEYFRAMES (reach over the cube, open, lower, close, lift, swing away, home) with
smooth cosine easing, publishing the SO-100 joint names with goal positions in radians at the given
rate (reliable, keep-last 10: what an ACTUATOR_SUBSCRIBER's default subscription accepts).
SIGINT or SIGTERM stops it with exit code 0.
"""

import argparse
import math
import sys
import time

from sensor_msgs.msg import JointState

from joshua_core.settings import NodeSettings, QosSettings, TopicSettings
from joshua_core.so100 import SO100_JOINTS
from joshua_runtime.errors import SettingsError
from joshua_runtime.node import JoshuaNode, run
from joshua_runtime.nodes import settings_checks

# (seconds to get there from the previous pose, pose in SO100_JOINTS order, radians).
# The loop starts and ends at home (upper arm up, forearm forward), the simulated arm's initial pose.
KEYFRAMES = (
    (2.0, (0.24, 0.55, -0.90, 1.54, 0.0, 0.9)),  # over the cube, gripper open
    (1.5, (0.24, 0.93, -0.90, 1.54, 0.0, 0.9)),  # lower around the cube
    (1.0, (0.24, 0.93, -0.90, 1.54, 0.0, -0.1)),  # close the gripper
    (2.0, (0.24, 0.45, -0.90, 1.54, 0.0, -0.1)),  # lift
    (2.5, (-0.6, 0.3, 0.2, 0.6, 1.5, 0.5)),  # swing away and roll the wrist
    (2.0, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)),  # home
)
CYCLE_S = sum(duration for duration, _ in KEYFRAMES)
DEFAULT_RATE_HZ = 50.0
DEFAULT_QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE"}


def scripted_positions(t: float) -> tuple[float, ...]:
    """The pose at `t` seconds into the loop (SO100_JOINTS order); it repeats every CYCLE_S."""
    t = t % CYCLE_S
    previous = KEYFRAMES[-1][1]
    for duration, pose in KEYFRAMES:
        if t < duration:
            blend = (1.0 - math.cos(math.pi * t / duration)) / 2.0
            return tuple(a + (b - a) * blend for a, b in zip(previous, pose))
        t -= duration
        previous = pose
    return KEYFRAMES[-1][1]


class ScriptedMotionNode(JoshuaNode):
    """Publishes scripted_positions() as JointState on the settings' topic at their rate_hz."""

    def start(self) -> None:
        names = list(self.settings.joint_names or SO100_JOINTS)
        unknown = [n for n in names if n not in SO100_JOINTS]
        if unknown:
            raise SettingsError(f"scripted motion has no joint {unknown[0]!r} (joints: {', '.join(SO100_JOINTS)})")
        self.names = names
        self.columns = [SO100_JOINTS.index(n) for n in names]
        self.commands = self.publisher(settings_checks.topic(self.settings))
        self.started = time.monotonic()
        self.timer = self.ros.create_timer(settings_checks.period_s(self.settings), self.publish)

    def publish(self) -> None:
        pose = scripted_positions(time.monotonic() - self.started)
        msg = JointState(name=self.names, position=[pose[c] for c in self.columns])
        msg.header.stamp = self.stamp()
        self.commands.publish(msg)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m joshua_runtime.sim.scripted_motion",
        description="Publish a looping SO-100 demo motion as JointState commands.",
    )
    parser.add_argument("--topic", required=True, help="command topic of the (simulated) actuator")
    parser.add_argument("--rate-hz", type=float, default=DEFAULT_RATE_HZ, help="publication rate")
    parser.add_argument("--joint-names", default="", help="comma-separated subset/order of the SO-100 joints")
    parser.add_argument("--name", default="scripted_motion", help="ROS node name")
    args = parser.parse_args(argv)
    if not args.rate_hz > 0:
        parser.error(f"--rate-hz must be positive, got {args.rate_hz}")
    settings = NodeSettings(
        name=args.name,
        rate_hz=args.rate_hz,
        joint_names=[n for n in args.joint_names.split(",") if n],
        topic=TopicSettings(name=args.topic, message_type="sensor_msgs/msg/JointState", qos=QosSettings(**DEFAULT_QOS)),
    )
    return run(ScriptedMotionNode, settings)


if __name__ == "__main__":
    sys.exit(main())
