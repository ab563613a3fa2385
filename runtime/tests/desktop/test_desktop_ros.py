"""The panel on a running robot over ROS: an ACTUATOR_SUBSCRIBER node process on an emulated bus.

The e-stop goes as a torque_off preset on `<command topic>/preset`; the actuator switches every servo off.
"""

import math

from desktop_helpers import IDS, JOINTS, close_panel, open_panel
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QPushButton
from rclpy.qos import QoSProfile, ReliabilityPolicy
from std_msgs.msg import String

from joshua_runtime.desktop.model import BUILTIN_PRESETS
from joshua_runtime.desktop.ros_worker import RosWorker, preset_topic
from joshua_runtime.drivers.calibration import uncalibrated
from testsupport.compiled_settings import compiled_node

STARTUP_TIMEOUT_MS = 30_000
WAIT_MS = 10_000  # generous: the machine may be busy; a pass returns at once
RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


def test_ros_panel_drives_a_running_actuator(qtbot, emulators, start_node, ros_client, screenshot):
    follower = emulators("ttyROSFOLLOWER")
    node = start_node(
        compiled_node(
            f'name: "follower_arm" type: ACTUATOR_SUBSCRIBER topic_name: "/follower/command" '
            f'serial_port: "{follower.link}" state_topic: "/follower/joint_states"'
        )
    )
    ros_client.listen(preset_topic("/follower/command"), String, RELIABLE)
    follower.move_by_hand(2, 1500)
    window = open_panel(qtbot, RosWorker("/follower/joint_states", "/follower/command"), timeout_ms=STARTUP_TIMEOUT_MS)
    try:
        assert window.link.text() == "ROS /follower/joint_states -> /follower/command", node.failure()
        qtbot.waitUntil(
            lambda: window.latest.joints["shoulder_lift"].position == uncalibrated(2).to_radians(1500), timeout=WAIT_MS
        )
        window.joint_panel.rows["shoulder_pan"].slider.setValue(-250)  # -25.0 degrees
        goal = uncalibrated(1).to_ticks(math.radians(-25.0))
        qtbot.waitUntil(lambda: follower.position(1) == goal, timeout=WAIT_MS)

        qtbot.mouseClick(window.findChild(QPushButton, "preset_rest"), Qt.MouseButton.LeftButton)
        rest = [uncalibrated(i).to_ticks(BUILTIN_PRESETS["rest"][joint]) for joint, i in zip(JOINTS, IDS)]
        qtbot.waitUntil(lambda: [follower.read_register(i, "Goal_Position") for i in IDS] == rest, timeout=WAIT_MS)
        qtbot.waitUntil(lambda: len(window.charts[0].times) > 10, timeout=WAIT_MS)
        assert window.health.texts["gripper"].text() == "not reported over this link"
        assert window.charts[2].latest("gripper") is None  # no temperature over ROS
        assert window.charts[2].empty_text == "not reported over this link"
        assert not window.joint_panel.rows["gripper"].torque.isEnabled()
        screenshot(window, "ros_panel")

        qtbot.mouseClick(window.estop, Qt.MouseButton.LeftButton)
        assert ros_client.spin_until(lambda: ros_client.last(preset_topic("/follower/command")), 5.0)
        assert ros_client.last(preset_topic("/follower/command")).data == "torque_off"
        qtbot.waitUntil(
            lambda: [follower.read_register(i, "Torque_Enable") for i in IDS] == [0] * len(IDS), timeout=WAIT_MS
        )  # the actuator took the e-stop: every servo is limp
    finally:
        close_panel(window)
