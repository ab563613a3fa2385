"""/diagnostics of the servo nodes over DDS, judged from emulated temperature, voltage and error bits."""

import signal

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.qos import QoSProfile, ReliabilityPolicy
from servo_helpers import SO100_JOINTS

from joshua_runtime.drivers import sts3215_protocol as proto
from testsupport.compiled_settings import compiled_node

STARTUP_TIMEOUT_S = 30.0
DATA_TIMEOUT_S = 5.0
RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
OK, WARN, ERROR = (DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR)


def by_joint(message: DiagnosticArray) -> dict[str, DiagnosticStatus]:
    return {status.name.split(": ", 1)[1]: status for status in message.status}


def levels(ros_client) -> dict[str, bytes]:
    message = ros_client.last("/diagnostics")
    return {joint: status.level for joint, status in by_joint(message).items()} if message else {}


def test_encoder_reports_each_servo_and_follows_its_temperature_voltage_and_errors(emulators, start_node, ros_client):
    leader = emulators("ttyDIAGNOSE", ids=[1, 2, 3])
    node = start_node(
        compiled_node(
            f'name: "leader" type: ENCODER_PUBLISHER topic_name: "/leader/joint_states" serial_port: "{leader.link}" '
            f'device_ids: [1, 2, 3] joint_names: ["pan", "lift", "elbow"] diagnostics_rate_hz: 10'
        )
    )
    ros_client.listen("/diagnostics", DiagnosticArray, RELIABLE)
    everything_ok = {"pan": OK, "lift": OK, "elbow": OK}
    assert ros_client.spin_until(lambda: levels(ros_client) == everything_ok, STARTUP_TIMEOUT_S), node.failure()
    publishers = ros_client.publishers_info("/diagnostics", DATA_TIMEOUT_S)
    assert [(p.node_name, p.topic_type) for p in publishers] == [("leader", "diagnostic_msgs/msg/DiagnosticArray")]
    pan = by_joint(ros_client.last("/diagnostics"))["pan"]
    assert (pan.name, pan.hardware_id, pan.message) == ("leader: pan", f"{leader.link} id 1", "OK")
    values = {item.key: item.value for item in pan.values}
    assert (values["temperature_c"], values["voltage_v"], values["read_failures"]) == ("30", "12.1", "0")

    leader.set_sensor(2, "Present_Temperature", 63)
    leader.set_sensor(3, "Present_Voltage", 35)
    expected = {"pan": OK, "lift": WARN, "elbow": ERROR}
    assert ros_client.spin_until(lambda: levels(ros_client) == expected, DATA_TIMEOUT_S), levels(ros_client)
    statuses = by_joint(ros_client.last("/diagnostics"))
    assert statuses["lift"].message == "temperature 63 C near 70 C"
    assert statuses["elbow"].message == "servo reports input voltage; voltage 3.5 V outside 4.0-14.0 V"

    leader.set_sensor(2, "Present_Temperature", 30)
    leader.set_sensor(3, "Present_Voltage", 121)
    leader.inject_error(1, proto.ERROR_OVERLOAD)
    expected = {"pan": ERROR, "lift": OK, "elbow": OK}
    assert ros_client.spin_until(lambda: levels(ros_client) == expected, DATA_TIMEOUT_S), levels(ros_client)
    assert by_joint(ros_client.last("/diagnostics"))["pan"].message == "servo reports overload"
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr


def test_a_bus_that_stops_answering_reads_as_errors_with_counted_failures(emulators, start_node, ros_client):
    leader = emulators("ttyDIAGLOST", ids=[1])
    node = start_node(
        compiled_node(
            f'name: "leader" type: ENCODER_PUBLISHER topic_name: "/leader/joint_states" serial_port: "{leader.link}" '
            f'device_ids: [1] joint_names: ["pan"] diagnostics_rate_hz: 10 rate_hz: 20'
        )
    )
    ros_client.listen("/diagnostics", DiagnosticArray, RELIABLE)
    assert ros_client.spin_until(lambda: levels(ros_client) == {"pan": OK}, STARTUP_TIMEOUT_S), node.failure()
    leader.stop()
    assert ros_client.spin_until(lambda: levels(ros_client) == {"pan": ERROR}, DATA_TIMEOUT_S)
    pan = by_joint(ros_client.last("/diagnostics"))["pan"]
    assert pan.message.startswith("servo id 1 unreadable: ")
    assert int({item.key: item.value for item in pan.values}["read_failures"]) >= 1
    node.stop(signal.SIGINT)


def test_six_servo_actuator_reports_every_joint(emulators, start_node, ros_client):
    follower = emulators("ttyDIAGFOLLOW")
    node = start_node(
        compiled_node(
            f'name: "follower" type: ACTUATOR_SUBSCRIBER topic_name: "/follower/command" serial_port: "{follower.link}"'
        )
    )
    ros_client.listen("/diagnostics", DiagnosticArray, RELIABLE)
    assert ros_client.spin_until(lambda: ros_client.last("/diagnostics"), STARTUP_TIMEOUT_S), node.failure()
    assert list(by_joint(ros_client.last("/diagnostics"))) == SO100_JOINTS
    code, _, stderr = node.stop(signal.SIGINT)
    assert code == 0, stderr
