"""The Fast DDS shared-memory files of a SIGKILLed node are removed once the supervisor reaps it; those of
live processes are left alone; those whose lock a peer held for a moment as the node died (Fast DDS tests a
peer's segment that way) are removed once it is released."""

import ctypes
import os
import signal
import subprocess
from pathlib import Path

from supervisor_harness import PYTHON, WAIT_S, Supervisor, build, quoted, robot, wait_until

from joshua_codegen.supervisor.policy import SHM_RECHECKS_S

SHM = Path("/dev/shm")
REMOVED = r"removed (\d+) Fast DDS shared-memory files"
LATER_LOOKS_S = sum(SHM_RECHECKS_S) + WAIT_S  # the supervisor's last look, with time to spare
SYS_PIDFD_GETFD = 438  # x86_64: a copy of another process's descriptor, sharing its open file (and its flock)

# argv: READY_FILE. A real rclpy node with a publisher and a subscription; writes its PID once up,
# stops cleanly on SIGINT.
ROS_NODE = r"""
import os, sys
import rclpy
from rclpy.executors import ExternalShutdownException
from std_msgs.msg import String
rclpy.init()
node = rclpy.create_node(f"shm_probe_{os.getpid()}")
node.create_publisher(String, "/shm_probe", 10)
node.create_subscription(String, "/shm_probe", lambda message: None, 10)
with open(sys.argv[1], "w") as ready:
    ready.write(str(os.getpid()))
try:
    while rclpy.ok():
        rclpy.spin_once(node, timeout_sec=0.1)
except (KeyboardInterrupt, ExternalShutdownException):
    pass
finally:
    node.destroy_node()
    rclpy.try_shutdown()
"""


def ros_node(tmp_path: Path, name: str) -> str:
    script = tmp_path / "ros_node.py"
    script.write_text(ROS_NODE)
    args = ", ".join(quoted(a) for a in [str(script), str(tmp_path / f"{name}.ready")])
    return f'node {{ name: "{name}" type: CUSTOM executable: "{PYTHON}" args: [{args}] restart: RESTART_NEVER critical: false }}'


def ready_pid(tmp_path: Path, name: str) -> int:
    path = tmp_path / f"{name}.ready"
    wait_until(lambda: path.exists() and path.read_text(), f"{name} to be up", timeout=30)
    return int(path.read_text())


def lock_descriptors(pid: int) -> dict[str, int]:
    """segment name -> the descriptor number of its lock file in process `pid`."""
    found = {}
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target.startswith(f"{SHM}/fastrtps_") and target.endswith("_el"):
            found[Path(target).name[: -len("_el")]] = int(fd.name)
    return found


def borrow_descriptor(pid: int, fd: int) -> int:
    """Process `pid`'s descriptor `fd`, copied into this process: a lock on it outlives `pid` until closed."""
    libc = ctypes.CDLL(None, use_errno=True)
    pidfd = os.pidfd_open(pid)
    try:
        copy = libc.syscall(SYS_PIDFD_GETFD, pidfd, fd, 0)
        if copy < 0:
            raise OSError(ctypes.get_errno(), "pidfd_getfd")
        return copy
    finally:
        os.close(pidfd)


def shm_files(pid: int) -> set[str]:
    """The Fast DDS segments a live process holds (by their lock files), with every companion file."""
    names = set()
    for segment in lock_descriptors(pid):
        names |= {name for name in (segment, f"{segment}_el", f"sem.{segment}_mutex") if (SHM / name).exists()}
    return names


def existing(names):
    return [name for name in names if (SHM / name).exists()]


def test_segments_of_a_sigkilled_node_are_removed_and_others_kept(tmp_path, ros_env):
    out = build(tmp_path, robot([ros_node(tmp_path, "victim"), ros_node(tmp_path, "bystander")], sigint=10))
    outside_env = dict(ros_env, FASTRTPS_DEFAULT_PROFILES_FILE=str(out / "fastdds_profile.xml"))
    outside = subprocess.Popen(
        [PYTHON, str(tmp_path / "ros_node.py"), str(tmp_path / "outside.ready")], env=outside_env
    )
    supervisor = Supervisor(out, env=ros_env)
    try:
        victim, bystander = ready_pid(tmp_path, "victim"), ready_pid(tmp_path, "bystander")
        outsider = ready_pid(tmp_path, "outside")
        wait_until(lambda: all(shm_files(pid) for pid in (victim, bystander, outsider)), "segments to exist")
        doomed, kept = shm_files(victim), shm_files(bystander) | shm_files(outsider)
        assert any(name.startswith("fastrtps_port") for name in doomed) and len(doomed) >= 4
        os.kill(victim, signal.SIGKILL)
        supervisor.wait_log(r"^.*victim: pid \d+ killed by SIGKILL")
        supervisor.wait_log(REMOVED)
        # a peer testing one of them just then keeps it for one of the later looks
        wait_until(lambda: not existing(doomed), "the victim's files to go", timeout=LATER_LOOKS_S)
        assert all((SHM / name).exists() for name in kept)
        assert shm_files(bystander) | shm_files(outsider) == kept
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 5  # a non-critical node failed for good
    finally:
        supervisor.close()
        outside.send_signal(signal.SIGINT)
        outside.wait()


def test_a_segment_whose_lock_a_peer_holds_as_the_node_dies_is_removed_once_the_peer_lets_go(tmp_path, ros_env):
    bystander = 'node { name: "bystander" type: CUSTOM executable: "/bin/sleep" args: ["600"] }'  # keeps the run going
    out = build(tmp_path, robot([ros_node(tmp_path, "victim"), bystander], sigint=10))
    supervisor = Supervisor(out, env=ros_env)
    try:
        victim = ready_pid(tmp_path, "victim")
        wait_until(lambda: len(lock_descriptors(victim)) >= 2, "segments to exist")
        doomed = shm_files(victim)
        held, fd = sorted(lock_descriptors(victim).items())[0]
        peer = borrow_descriptor(victim, fd)  # the lock stays held through this copy, as a peer's test would
        try:
            os.kill(victim, signal.SIGKILL)
            supervisor.wait_log(REMOVED)  # the segments it could remove as it reaped the victim: all others
            assert (SHM / held).exists() and (SHM / f"{held}_el").exists()
        finally:
            os.close(peer)
        # by a later look (another supervisor running beside this one may come first: its rule covers it too)
        wait_until(lambda: not existing(doomed), "the held segment to go", timeout=LATER_LOOKS_S)
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 5  # a non-critical node failed for good
    finally:
        supervisor.close()
