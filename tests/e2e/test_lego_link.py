"""A lost Bluetooth link of the LEGO base is loud and heals, against `joshua-emulate pybricks` processes.

The emulator is restarted (a re-plugged dongle), killed for good, frozen, or told to drop the link;
the base node runs as a process, alone or under its generated supervisor, and an rclpy client
watches /odom and /diagnostics. How fast a loss is reported is measured by bench/lego.py.
"""

import json
import re
import signal
import subprocess
import sys
import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.qos import QoSProfile, ReliabilityPolicy

from joshua_core.device_link import DEVICE_SILENCE_S
from joshua_runtime.drivers.pybricks import HUB_RECONNECT_WINDOW_S
from testsupport.compiled_settings import compiled_settings
from testsupport.hub_emulator import HubEmulator, wait_for_text
from testsupport.joshuac_cli import ROOT, joshuac
from testsupport.node_process import NodeProcess

CONFIG = ROOT / "config" / "robots" / "lego_bot.pbtxt"
RELIABLE = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
STARTUP_TIMEOUT_S = 40.0
EVENT_TIMEOUT_S = 15.0  # a bound for a busy machine; bench/lego.py measures the real figures
SUPERVISOR_STOP_TIMEOUT_S = 30.0
COMMAND_PERIOD_S = 0.1
HUB = "Pybricks Hub"
LINK_STATUS = "base: Pybricks hub"
LOST = rf"\[base\]: link to Pybricks hub '{HUB}' lost \((?P<reason>[^)]*)\)"
RECONNECTED = rf"\[base\]: reconnected to Pybricks hub '{HUB}' after "
OK, ERROR = DiagnosticStatus.OK, DiagnosticStatus.ERROR


def base_settings(hub: HubEmulator) -> dict:
    return compiled_settings(CONFIG.read_text(), [f"base.ble_transport={hub.hci}"])["base"]


def link_status(ros_client) -> DiagnosticStatus | None:
    """The newest status of the base's hub link on /diagnostics."""
    for message in reversed(ros_client.messages("/diagnostics")):
        for status in message.status:
            if status.name == LINK_STATUS:
                return status
    return None


def link_level(ros_client) -> bytes | None:
    status = link_status(ros_client)
    return status.level if status is not None else None


def watch(ros_client) -> None:
    ros_client.listen("/odom", Odometry, RELIABLE)
    ros_client.listen("/diagnostics", DiagnosticArray, RELIABLE, keep=50)


def drive(ros_client, seconds: float, speed_m_s: float = 0.1) -> None:
    """Publish a forward Twist every COMMAND_PERIOD_S for `seconds`."""
    cmd_vel = ros_client.publisher("/cmd_vel", Twist, RELIABLE)
    ros_client.spin_until(lambda: cmd_vel.get_subscription_count() > 0, EVENT_TIMEOUT_S)
    command = Twist()
    command.linear.x = speed_m_s
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        cmd_vel.publish(command)
        ros_client.spin_until(lambda: False, COMMAND_PERIOD_S)


def odometry_resumes(ros_client) -> bool:
    count = ros_client.count("/odom")
    return ros_client.spin_until(lambda: ros_client.count("/odom") > count + 10, EVENT_TIMEOUT_S)


def test_a_restarted_hub_is_reported_and_the_base_reconnects_with_its_wheels_stopped(tmp_path, ros_env, ros_client):
    hub = HubEmulator(tmp_path).start()
    base = NodeProcess(base_settings(hub), ros_env, stderr_path=tmp_path / "base.log")
    try:
        watch(ros_client)
        up = ros_client.spin_until(lambda: link_level(ros_client) == OK and ros_client.last("/odom"), STARTUP_TIMEOUT_S)
        assert up, base.failure()
        drive(ros_client, 1.0)
        assert ros_client.last("/odom").pose.pose.position.x > 0.03, "the car did not move"
        hub.stop(signal.SIGKILL)  # the dongle pulled out
        assert ros_client.spin_until(lambda: link_level(ros_client) == ERROR, EVENT_TIMEOUT_S), base.stderr_text()
        assert "Bluetooth controller lost" in link_status(ros_client).message
        lost = wait_for_text(base.stderr_path, LOST, EVENT_TIMEOUT_S)
        assert lost and lost["reason"] == "Bluetooth controller lost", base.stderr_text()
        x_before = ros_client.last("/odom").pose.pose.position.x

        hub.start()  # plugged in again: a fresh hub, its program not loaded, its wheel angles at 0
        reconnected = ros_client.spin_until(lambda: link_level(ros_client) == OK, HUB_RECONNECT_WINDOW_S)
        assert reconnected, base.stderr_text()
        assert wait_for_text(base.stderr_path, RECONNECTED, EVENT_TIMEOUT_S), base.stderr_text()
        assert odometry_resumes(ros_client), "no odometry after the reconnection"
        odom = ros_client.last("/odom")
        assert abs(odom.twist.twist.linear.x) < 1e-3, "the wheels turn with no Twist since the loss"
        assert abs(odom.pose.pose.position.x - x_before) < 0.01, "the pose jumped when the hub came back"
        drive(ros_client, 1.0)
        assert ros_client.last("/odom").pose.pose.position.x > x_before + 0.03, "the car does not drive again"
    finally:
        code, _, stderr = base.stop()
        hub.stop()
    assert code == 0, stderr
    assert "Traceback" not in stderr and "timed out" not in stderr, stderr


def test_an_injected_link_drop_is_logged_by_the_emulator_and_reported_by_the_node(tmp_path, ros_env, ros_client):
    hub = HubEmulator(tmp_path, "--drop-link-after", "5").start()
    base = NodeProcess(base_settings(hub), ros_env, stderr_path=tmp_path / "base.log")
    try:
        watch(ros_client)
        assert ros_client.spin_until(lambda: ros_client.last("/odom"), STARTUP_TIMEOUT_S), base.failure()
        drive(ros_client, 1.0)
        fault = wait_for_text(hub.log_path, r"fault: dropping the link on stdin command 5 \(--drop-link-after\)", 1.0)
        assert fault, hub.log()
        lost = wait_for_text(base.stderr_path, LOST, EVENT_TIMEOUT_S)
        assert lost and lost["reason"] == "the hub closed the link", base.stderr_text()
        assert wait_for_text(base.stderr_path, RECONNECTED, HUB_RECONNECT_WINDOW_S), base.stderr_text()
        assert odometry_resumes(ros_client), "no odometry after the reconnection"
    finally:
        code, _, stderr = base.stop()
        hub.stop()
    assert code == 0, stderr


def test_sigint_during_a_hung_reconnect_ends_the_base_with_0_and_no_traceback(tmp_path, ros_env, ros_client):
    hub = HubEmulator(tmp_path).start()
    base = NodeProcess(base_settings(hub), ros_env, stderr_path=tmp_path / "base.log")
    try:
        watch(ros_client)
        assert ros_client.spin_until(lambda: ros_client.last("/odom"), STARTUP_TIMEOUT_S), base.failure()
        hub.pause()  # the controller stops answering; its TCP connection stays open
        lost = wait_for_text(base.stderr_path, LOST, EVENT_TIMEOUT_S)
        assert lost and lost["reason"] == f"no wheel angles for {DEVICE_SILENCE_S:g} s", base.stderr_text()
        assert ros_client.spin_until(lambda: link_level(ros_client) == ERROR, EVENT_TIMEOUT_S)
        ros_client.spin_until(lambda: False, 2.0)  # a reconnection attempt hangs on the frozen controller
        code, _, stderr = base.stop(signal.SIGINT)
    finally:
        base.kill()
        hub.stop()
    assert code == 0, stderr
    assert "Traceback" not in stderr and "timed out" not in stderr, stderr


def ctl_status(out, sock) -> dict:
    result = subprocess.run(
        [sys.executable, str(out / "supervisor.py"), "ctl", "--control-socket", str(sock), "status", "--json"],
        capture_output=True,
        text=True,
        timeout=EVENT_TIMEOUT_S,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    return {node["name"]: node for node in json.loads(result.stdout)["nodes"]}


def test_a_hub_gone_for_good_ends_the_base_with_3_and_the_supervisor_restarts_it(tmp_path, ros_env):
    hub = HubEmulator(tmp_path).start()
    out, sock, log_path = tmp_path / "out", tmp_path / "run" / "lego.sock", tmp_path / "supervisor.log"
    built = joshuac("build", CONFIG, "-o", out, "--set", f"base.ble_transport={hub.hci}", env=ros_env)
    assert built.returncode == 0, built.stderr
    with open(log_path, "w") as log:
        supervisor = subprocess.Popen(
            [sys.executable, str(out / "supervisor.py"), "--control-socket", str(sock)],
            stdout=log,
            stderr=subprocess.STDOUT,
            env=ros_env,
        )
    try:
        assert wait_for_text(log_path, r"base: ready after", STARTUP_TIMEOUT_S), log_path.read_text()
        assert ctl_status(out, sock)["base"]["restarts"] == 0
        hub.stop(signal.SIGKILL)
        assert wait_for_text(log_path, LOST, EVENT_TIMEOUT_S), log_path.read_text()
        assert ctl_status(out, sock)["base"]["state"] == "running"  # still trying, within the window
        exited = wait_for_text(
            log_path, r"base: pid \d+ exited with code (\d+)", HUB_RECONNECT_WINDOW_S + EVENT_TIMEOUT_S
        )
        assert exited and exited.group(1) == "3", log_path.read_text()
        gave_up = rf"^base: error: link to Pybricks hub '{HUB}' lost for {HUB_RECONNECT_WINDOW_S:g} s \("
        assert re.search(gave_up, log_path.read_text(), re.M), log_path.read_text()
        assert wait_for_text(log_path, r"base: restarting in", EVENT_TIMEOUT_S), log_path.read_text()
        assert ctl_status(out, sock)["base"]["restarts"] >= 1
    finally:
        supervisor.send_signal(signal.SIGINT)
        try:
            supervisor.wait(SUPERVISOR_STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            supervisor.kill()
            supervisor.wait()
        hub.stop()
    assert "Traceback" not in log_path.read_text(), log_path.read_text()
