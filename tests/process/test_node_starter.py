"""Python nodes forked from the node starter run as exec'd ones do: children of the supervisor, each in its cgroup,
with its command line, restarted through it, stopped by the cascade; without it they start their own interpreters."""

import os
import re
import signal
from pathlib import Path

from supervisor_harness import PYTHON, Supervisor, alive, build, command_line, parent_of, robot, wait_until

NODES = [
    'node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader" rate_hz: 20 }',
    'node { name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader" }',
]
READY = r"supervisor: ready: 2 of 2 nodes ready"
START_WAIT_S = 60.0  # two nodes importing rclpy on a machine the whole suite shares
NODE_MARK = b"JOSHUA_SUPERVISOR_NODE="  # in the environment a process was exec'd with: the supervisor exec'd it
# A sitecustomize that makes the first import of rclpy in a process wait, so that a stop comes while it imports.
SLOW_RCLPY = """
import sys, time

class SlowRclpy:
    def find_spec(self, name, path=None, target=None):
        if name == "rclpy":
            sys.meta_path.remove(self)
            time.sleep({seconds})
        return None

sys.meta_path.insert(0, SlowRclpy())
"""


def start(tmp_path, env, *options: str) -> tuple[Path, Supervisor]:
    out = build(tmp_path, robot(NODES, sigint=3, sigterm=1))
    supervisor = Supervisor(out, "--no-control", "--log-dir", str(tmp_path / "logs"), *options, env=env)
    supervisor.wait_log(READY, timeout=START_WAIT_S)
    return out, supervisor


def node_pids(supervisor: Supervisor, name: str) -> list[int]:
    return [
        int(pid) for pid in re.findall(rf"^\[ *[\d.]+\] {name}: started pid (\d+) \(Python\)", supervisor.log(), re.M)
    ]


def starter_pid(supervisor: Supervisor) -> int:
    return int(supervisor.wait_log(r"node-starter: started pid (\d+)").group(1))


def exec_environment(pid: int) -> bytes:
    """The environment `pid` was exec'd with (a forked process shows its exec'd ancestor's)."""
    return Path(f"/proc/{pid}/environ").read_bytes()


def forked_from_the_starter(pid: int) -> bool:
    """Whether `pid` shows the starter's environment: the robot's, without a node's mark."""
    environment = exec_environment(pid)
    return b"ROS_DOMAIN_ID=" in environment and NODE_MARK not in environment


def stop(supervisor: Supervisor) -> int:
    supervisor.signal()
    try:
        return supervisor.wait(timeout=30)
    finally:
        supervisor.close()


def test_python_nodes_are_forked_from_the_starter_as_children_of_the_supervisor_each_in_its_cgroup(tmp_path, ros_env):
    out, supervisor = start(tmp_path, ros_env)
    try:
        starter = starter_pid(supervisor)
        assert "node-starter: ready: Python nodes are forked from it" in supervisor.log()
        for name in ("leader", "follower"):
            [pid] = node_pids(supervisor, name)
            assert parent_of(pid) == supervisor.pid
            assert command_line(pid)[:2] == [PYTHON, str(out / "nodes" / f"{name}.py")]
            assert Path(f"/proc/{pid}/cgroup").read_text().rstrip().endswith(f"/joshua-r-{supervisor.pid}/{name}")
            assert forked_from_the_starter(pid)
            assert os.getsid(pid) == pid  # a session of its own, as an exec'd node has
        assert parent_of(starter) == supervisor.pid
    finally:
        code = stop(supervisor)
    assert code == 0, supervisor.log()
    assert not alive(starter)
    assert "exited with code 0" in supervisor.log().split("leader: final state:")[1].splitlines()[0]


def test_a_crashed_node_is_forked_again_by_the_starter(tmp_path, ros_env):
    _, supervisor = start(tmp_path, ros_env)
    try:
        starter = starter_pid(supervisor)
        [first] = node_pids(supervisor, "leader")
        os.kill(first, signal.SIGKILL)
        wait_until(lambda: len(node_pids(supervisor, "leader")) == 2, "the leader's restart", START_WAIT_S)
        second = node_pids(supervisor, "leader")[1]
        wait_until(lambda: parent_of(second) == supervisor.pid, "the supervisor adopting the new leader")
        assert forked_from_the_starter(second)
        assert alive(starter)
        wait_until(lambda: supervisor.log().count("leader: ready after") == 2, "the leader ready again", START_WAIT_S)
    finally:
        code = stop(supervisor)
    assert code == 0, supervisor.log()  # it ran again, and stopped cleanly


def test_without_the_starter_python_nodes_start_their_own_interpreters(tmp_path, ros_env):
    _, supervisor = start(tmp_path, ros_env)
    try:
        starter = starter_pid(supervisor)
        os.kill(starter, signal.SIGKILL)
        supervisor.wait_log(
            rf"node-starter: warning: pid {starter} killed by SIGKILL; each Python node starts its own interpreter"
        )
        [first] = node_pids(supervisor, "follower")
        os.kill(first, signal.SIGKILL)
        wait_until(lambda: len(node_pids(supervisor, "follower")) == 2, "the follower's restart", START_WAIT_S)
        second = node_pids(supervisor, "follower")[1]
        wait_until(lambda: NODE_MARK in exec_environment(second), "the new follower exec'd by the supervisor")
    finally:
        code = stop(supervisor)
    assert code == 0, supervisor.log()  # it ran again, and stopped cleanly


def test_no_node_starter_runs_each_python_node_in_its_own_interpreter(tmp_path, ros_env):
    _, supervisor = start(tmp_path, ros_env, "--no-node-starter")
    try:
        assert "node-starter" not in supervisor.log()
        for name in ("leader", "follower"):  # ready, so exec'd long since
            assert NODE_MARK in exec_environment(node_pids(supervisor, name)[0])
    finally:
        code = stop(supervisor)
    assert code == 0, supervisor.log()


def test_a_stop_while_the_starter_imports_ends_the_run_with_nothing_left(tmp_path, ros_env):
    hooks = tmp_path / "hooks"
    hooks.mkdir()
    (hooks / "sitecustomize.py").write_text(SLOW_RCLPY.format(seconds=30))
    env = dict(ros_env, PYTHONPATH=os.pathsep.join(filter(None, [str(hooks), ros_env.get("PYTHONPATH")])))
    out = build(tmp_path, robot(NODES, sigint=3, sigterm=1))
    supervisor = Supervisor(out, "--no-control", "--log-dir", str(tmp_path / "logs"), env=env)
    try:
        starter = starter_pid(supervisor)
        supervisor.signal()
        code = supervisor.wait(timeout=10)
    finally:
        supervisor.close()
    assert code == 0, supervisor.log()
    assert "started pid" not in supervisor.log().split("node-starter: started pid")[1]  # no node was started
    assert not alive(starter)
