"""The seed's leader/follower description run by its generated supervisor with the C++ nodes, end to end.

With `cpp_bin_dir` pointing at build/bin, the encoder and the actuator run as C++ processes on two
emulated buses and the follower tracks the leader; the camera, which has no C++ binary, runs Python from
the start (the build knows it: no fallback at run time). The binaries tell the supervisor they are ready
over sd_notify.
"""

import re
import signal
import subprocess
import sys

import cv2
import numpy as np
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Image, JointState

from testsupport.joshuac_cli import ROOT, joshuac

STARTUP_TIMEOUT_S = 40.0
TRACKING_TIMEOUT_S = 15.0
SHUTDOWN_TIMEOUT_S = 60.0  # the recorder holds its stop (asking for more time) while its save waits for LeRobot
TRACKING_TOLERANCE_TICKS = 3
RELIABLE_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
SENSOR_QOS = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)
POSES = ({1: 1500, 2: 2500, 3: 1800, 4: 2300, 5: 1000, 6: 2600}, {1: 2600, 2: 1400, 3: 3000, 4: 900, 5: 2000, 6: 1200})


def write_video(path) -> None:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 10, (64, 48))
    for i in range(10):
        writer.write(np.full((48, 64, 3), 20 * i, np.uint8))
    writer.release()


def test_leader_follower_runs_its_servo_nodes_in_cpp(tmp_path, ros_env, ros_client, buses, cpp_bin_dir):
    leader_bus, follower_bus = buses("ttyLEADER"), buses("ttyFOLLOWER")
    video = tmp_path / "camera.avi"
    write_video(video)
    out = tmp_path / "out"
    overrides = [f"encoder_publisher.serial_port={leader_bus.link}",
                 f"actuator_subscriber.serial_port={follower_bus.link}",
                 f"camera_publisher.video_source={video}",
                 f"data_subscriber.output_directory={tmp_path / 'episodes'}",
                 f"cpp_bin_dir={cpp_bin_dir}"]
    built = joshuac("build", ROOT / "config" / "robots" / "so100_leader_follower.pbtxt", "-o", out,
                    *[arg for override in overrides for arg in ("--set", override)])
    assert built.returncode == 0, built.stderr
    supervisor = subprocess.Popen([sys.executable, str(out / "supervisor.py")], env=ros_env, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True)
    try:
        ros_client.listen("/leader/joint_states", JointState, RELIABLE_QOS)
        ros_client.listen("/camera/image_raw", Image, SENSOR_QOS)
        # The Python camera too: a robot stopped while its Python nodes still import is another test's matter.
        assert ros_client.spin_until(lambda: ros_client.last("/leader/joint_states") is not None
                                     and ros_client.last("/camera/image_raw") is not None, STARTUP_TIMEOUT_S)
        assert follower_bus.wait_until(
            lambda: [follower_bus.read_register(i, "Torque_Enable") for i in range(1, 7)] == [1] * 6, STARTUP_TIMEOUT_S)
        for pose in POSES:
            for servo_id, ticks in pose.items():
                leader_bus.move_by_hand(servo_id, ticks)

            def follower_tracks(pose=pose) -> bool:
                return all(abs(follower_bus.position(i) - t) <= TRACKING_TOLERANCE_TICKS for i, t in pose.items())

            assert follower_bus.wait_until(follower_tracks, TRACKING_TIMEOUT_S), {
                i: follower_bus.position(i) for i in pose}
    finally:
        supervisor.send_signal(signal.SIGINT)
        try:
            output, _ = supervisor.communicate(timeout=SHUTDOWN_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            supervisor.kill()
            output, _ = supervisor.communicate()
    assert supervisor.returncode == 0, output
    for node in ("encoder_publisher", "actuator_subscriber"):
        binary = re.escape(str(cpp_bin_dir / node))
        assert re.search(rf"^\[ *[0-9.]+\] {node}: started pid [0-9]+ \(C\+\+\): {binary} --ros-args", output,
                         re.MULTILINE), output
        assert re.search(rf"^\[ *[0-9.]+\] {node}: pid [0-9]+ exited with code 0 ", output, re.MULTILINE), output
        # Ready when the binary says so (sd_notify), with what it serves.
        assert re.search(rf"^\[ *[0-9.]+\] {node}: ready after [0-9.]+ s: publishing /diagnostics", output,
                         re.MULTILINE), output
    warnings = re.findall(r"^\[ *[0-9.]+\] (\S+): warning: C\+\+ binary", output, re.MULTILINE)
    assert warnings == [], output  # every binary the build asks for exists
    assert re.search(r"^\[ *[0-9.]+\] camera_publisher: started pid [0-9]+ \(Python\): ", output, re.MULTILINE), output
    assert [follower_bus.read_register(i, "Torque_Enable") for i in range(1, 7)] == [0] * 6  # released at exit
