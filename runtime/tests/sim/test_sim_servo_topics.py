"""The simulation stands in for the servo nodes' and the base's /diagnostics and the preset channel too, as the manifest says."""

import signal

import pytest
import sim_settings
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import JointState
from sim_ros import RELIABLE, STARTUP_TIMEOUT_S
from std_msgs.msg import String

from joshua_runtime.presets import BUILTIN_PRESETS
from testsupport.compiled_settings import compiled_settings
from testsupport.joshuac_cli import ROOT

CONVERGE_TIMEOUT_S = 20.0
TOLERANCE_RAD = 0.03
REST = [BUILTIN_PRESETS["rest"][joint] for joint in sim_settings.SO100_JOINTS]


def test_simulated_arm_reports_diagnostics_and_follows_presets(start_node, ros_client):
    process = start_node(sim_settings.simulation(sim_settings.ENCODER, sim_settings.ACTUATOR))
    ros_client.listen("/diagnostics", DiagnosticArray, RELIABLE)
    ros_client.listen("/arm/present", JointState, RELIABLE)
    presets = ros_client.publisher("/arm/command/preset", String, RELIABLE)
    command = ros_client.publisher("/arm/command", JointState, RELIABLE)
    try:
        assert ros_client.spin_until(lambda: ros_client.last("/diagnostics"), STARTUP_TIMEOUT_S), process.failure()
        statuses = ros_client.last("/diagnostics").status
        joints = sim_settings.SO100_JOINTS
        expected = [f"{node}: {joint}" for node in ("arm_encoder", "arm_actuator") for joint in joints]
        assert [s.name for s in statuses] == expected
        assert {(s.level, s.message) for s in statuses} == {(DiagnosticStatus.OK, "simulated")}

        def at(pose):
            state = ros_client.last("/arm/present")
            return state is not None and list(state.position) == pytest.approx(pose, abs=TOLERANCE_RAD)

        rest = lambda: presets.publish(String(data="rest"))  # noqa: E731
        assert ros_client.spin_until(lambda: at(REST), CONVERGE_TIMEOUT_S, every=rest)
        ros_client.spin_until(lambda: False, 0.5, every=lambda: presets.publish(String(data="torque_off")))
        goal = JointState(name=joints, position=[0.0] * 6)
        ros_client.spin_until(lambda: False, 1.0, every=lambda: command.publish(goal))
        assert at(REST), "goals moved the arm after torque_off"
        presets.publish(String(data="torque_on"))
        assert ros_client.spin_until(lambda: at([0.0] * 6), CONVERGE_TIMEOUT_S, every=lambda: command.publish(goal))
    finally:
        code, _, stderr = process.stop(signal.SIGINT)
    assert code == 0, stderr


def test_the_simulated_lego_car_reports_its_base_on_diagnostics(start_node, ros_client):
    config = ROOT / "config" / "robots" / "lego_bot.pbtxt"
    process = start_node(compiled_settings(config.read_text(), ["mode=MODE_SIMULATION"])["simulation"])
    ros_client.listen("/diagnostics", DiagnosticArray, RELIABLE)
    try:
        assert ros_client.spin_until(lambda: ros_client.last("/diagnostics"), STARTUP_TIMEOUT_S), process.failure()
        statuses = ros_client.last("/diagnostics").status
        assert [(s.name, s.level, s.message) for s in statuses] == [
            ("base: Pybricks hub", DiagnosticStatus.OK, "simulated")
        ]
    finally:
        code, _, stderr = process.stop(signal.SIGINT)
    assert code == 0, stderr
