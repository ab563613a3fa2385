"""ACTUATOR_SUBSCRIBER: drives an STS3215 bus (e.g. a follower arm) from JointState commands or action chunks.

On start the servos hold their present pose and torque goes on. Each command on `topic` is matched to
`joint_names` by name (absent joints keep their goal), converted to raw goals clamped to the
calibrated range, and sent at once in one SYNC_WRITE. Only positions are used: a leader's present
velocity is no speed limit. A clamped goal is logged (at most every CLAMP_LOG_INTERVAL_S) and noted
on /diagnostics. With `state_topic` set, the bus's present joint states are published there every
1/rate_hz. Torque goes off when the node stops, unless keep_torque_on_exit is set.

With a trajectory_msgs/msg/JointTrajectory topic, each chunk is followed by nodes/trajectory_follower.py:
every 1/rate_hz its goal of that moment goes out like a command (clamped, feeding the watchdog); when
the chunk is over its last point is held, and command_timeout_s counts from then.

Preset commands (std_msgs/String) on `<topic>/preset`: `torque_on`, `torque_off` (the e-stop; torque
stays off until `torque_on`) and pose names (home, rest, grip_open and the description's `preset`s),
which move like a goal. With command_timeout_s set, a silence that long stops the arm once
(on_command_timeout: HOLD_POSITION holds the present position, RELEASE_TORQUE lets it go limp); the
next goal or pose resumes it.
"""

import math
import time

from std_msgs.msg import String

from joshua_core.servo_topics import FIXED_QOS, TORQUE_ON, preset_topic
from joshua_core.settings import QosSettings
from joshua_runtime import presets
from joshua_runtime.convert.joint_state import (
    joint_state_to_action,
    perception_to_joint_state,
)
from joshua_runtime.drivers.sts3215_health import WARN, Finding
from joshua_runtime.errors import DeviceError, SettingsError
from joshua_runtime.node import JoshuaNode
from joshua_runtime.nodes import settings_checks
from joshua_runtime.nodes.command_guard import CommandWatchdog, clamp_goals
from joshua_runtime.nodes.servo_bus import BusGuard, bus_from_settings
from joshua_runtime.nodes.servo_diagnostics import ServoDiagnostics
from joshua_runtime.nodes.trajectory_follower import ChunkCommands, is_trajectory
from joshua_runtime.qos import qos_profile

CLAMP_LOG_INTERVAL_S = 1.0
RELEASE_TORQUE = "RELEASE_TORQUE"


class ActuatorSubscriber(JoshuaNode):
    bus = None

    def start(self) -> None:
        period = settings_checks.period_s(self.settings)
        self.poses = presets.poses(_own_presets(self.settings))
        self.bus = bus_from_settings(self.settings)
        self.bus.open()
        self.bus.enable_torque()
        self.torque_on = True  # off after a torque_off preset until torque_on
        self.released_by_watchdog = False
        self.guard = BusGuard(self.bus, self.log, on_reconnect=self._restore_torque)
        self.diagnostics = ServoDiagnostics(self, self.guard)
        self.frame_id = self.settings.frame_id
        self.next_clamp_log = 0.0
        topic = settings_checks.topic(self.settings)
        if is_trajectory(topic):
            self.chunks = ChunkCommands(self, topic, self.bus.joint_names, period, self._drive_chunk)
        else:
            self.subscription(topic, self._command)
        self.ros.create_subscription(
            String, preset_topic(topic.name), self._preset, qos_profile(QosSettings(**FIXED_QOS))
        )
        self.watchdog = None
        if self.settings.command_timeout_s > 0:
            self.watchdog = CommandWatchdog(self.settings.command_timeout_s)
            self.ros.create_timer(min(period, self.settings.command_timeout_s / 4), self._watch)
        if self.settings.HasField("state_topic"):
            self.joint_states = self.publisher(self.settings.state_topic)
            self.ros.create_timer(period, self._publish_state)

    def _command(self, message) -> None:
        action = joint_state_to_action(message, self.bus.joint_names)
        if len(action.position) == len(self.bus.ids):
            self._drive(list(action.position))

    def _drive_chunk(self, goals) -> None:
        self._drive([float(goal) for goal in goals])

    def _drive(self, goals: list[float]) -> None:
        """Send goal positions (rad, NaN: leave alone), clamped to the calibrated range, and feed the watchdog."""
        if self.watchdog is not None:
            self.watchdog.feed(time.monotonic())
            if self.released_by_watchdog and self.torque_on:
                self.log.info("goal received: torque on again")
                self.guard.call(self.bus.enable_torque)
            self.released_by_watchdog = False
            self.diagnostics.condition = None
        ticks, clamped = clamp_goals(self.bus.calibration, self.bus.joint_names, goals)
        self.guard.call(self.bus.sync_write, "Goal_Position", ticks)
        if clamped:
            self._report(clamped)

    def _report(self, clamped) -> None:
        self.diagnostics.count("goals_clamped", len(clamped))
        for goal in clamped:
            self.diagnostics.note(self.bus.ids[self.bus.joint_names.index(goal.joint)], Finding(WARN, goal.describe()))
        now = time.monotonic()
        if now >= self.next_clamp_log:
            self.next_clamp_log = now + CLAMP_LOG_INTERVAL_S
            self.log.warning("outside the calibrated range: " + "; ".join(goal.describe() for goal in clamped))

    def _preset(self, message: String) -> None:
        name = message.data.strip()
        action = presets.expand(name, self.poses, self.bus.joint_names)
        if action is None:
            known = ", ".join(presets.TORQUE_PRESETS + tuple(self.poses))
            self.log.warning(f"unknown preset {name!r}: known are {known}")
            return
        if action.preset_commands:
            self.torque_on = name == TORQUE_ON
            self.released_by_watchdog = False
            self.log.info(f"preset {name}")
            self.guard.call(self.bus.write_action, action)
        elif any(not math.isnan(goal) for goal in action.position):
            self._drive(list(action.position))

    def _watch(self) -> None:
        if not self.watchdog.expired(time.monotonic()):
            return
        timeout = self.settings.command_timeout_s
        if not self.torque_on:
            return  # torque is already off (torque_off preset): nothing to stop
        if self.settings.on_command_timeout == RELEASE_TORQUE:
            self.log.warning(f"no goal for {timeout:g} s: torque off until the next goal")
            self.released_by_watchdog = True
            self.guard.call(self.bus.disable_torque)
            self.diagnostics.condition = Finding(WARN, f"no goal for {timeout:g} s: torque released")
        else:
            self.log.warning(f"no goal for {timeout:g} s: holding the present position")
            self.guard.call(self._hold)
            self.diagnostics.condition = Finding(WARN, f"no goal for {timeout:g} s: holding position")

    def _hold(self) -> None:
        self.bus.sync_write("Goal_Position", self.bus.sync_read("Present_Position"))

    def _restore_torque(self) -> None:
        """After a reconnect: torque as it was (a power-cycled servo starts limp)."""
        if self.torque_on and not self.released_by_watchdog:
            self.bus.enable_torque()

    def _publish_state(self) -> None:
        packet = self.guard.call(self.bus.read_state)
        if packet is not None:
            self.joint_states.publish(perception_to_joint_state(packet, frame_id=self.frame_id))

    def close(self) -> None:
        if self.bus is None:
            return
        try:
            if self.bus.is_open and not self.settings.keep_torque_on_exit:
                self.bus.disable_torque()
        except DeviceError as exc:
            self.log.warning(f"torque left on: {exc}")
        finally:
            self.bus.close()


def _own_presets(settings) -> dict[str, dict[str, float]]:
    """The description's presets by name; SettingsError for one that names a joint the bus does not have."""
    _, joints = settings_checks.joints(settings)
    own = {}
    for preset in settings.preset:
        unknown = sorted(set(preset.positions) - set(joints))
        if unknown:
            raise SettingsError(f"preset {preset.name!r} names joint {unknown[0]!r}, not one of {', '.join(joints)}")
        own[preset.name] = dict(preset.positions)
    return own
