"""LeRobot's own async inference (policy_server + RobotClient) on the bench's data, measured like the ROS setups.

The robot is a LeRobot `Robot` made for the bench: its observation is the same camera picture and joint
state the ROS setups publish (testsupport/tiny_act.py), its `send_action` is the actuator, where commands
are counted (the policy server and the client write LeRobot's logs/ into the working directory). The RobotClient is LeRobot's own, only watched: which observation each executed action came
from (its chunk's first timestamp) and when it was executed.
"""

import socket
import subprocess
import sys
import threading
import time

from lerobot.async_inference.configs import RobotClientConfig
from lerobot.async_inference.robot_client import RobotClient

from support.benchrobot import BenchRobotConfig
from testsupport import tiny_act

SERVER_START_TIMEOUT_S = 120.0
SERVER_STOP_TIMEOUT_S = 10.0


class WatchedClient(RobotClient):
    """LeRobot's RobotClient, noting for each executed action when it ran and the observation it came from."""

    def __init__(self, config: RobotClientConfig):
        super().__init__(config)
        self.origin: dict[int, float] = {}  # timestep -> timestamp of the observation its chunk came from
        self.executed: list[float] = []  # wall-clock times of actions sent to the robot
        self.reactions: list[float] = []  # observation -> first executed action of its chunk (s)
        self._seen: set[float] = set()

    def _aggregate_action_queues(self, incoming_actions, aggregate_fn=None):
        if incoming_actions:
            observed = incoming_actions[0].get_timestamp()
            for action in incoming_actions:
                self.origin[action.get_timestep()] = observed
        return super()._aggregate_action_queues(incoming_actions, aggregate_fn)

    def control_loop_action(self, verbose: bool = False):
        performed = super().control_loop_action(verbose)
        now = time.time()
        self.executed.append(now)
        observed = self.origin.get(self.latest_action)
        if observed is not None and observed not in self._seen:
            self._seen.add(observed)
            self.reactions.append(now - observed)
        return performed


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def measure(policy_dir, fps: int, seconds: float, warm_up_s: float, env: dict) -> tuple[list[float], list[float]]:
    """(times of executed actions, reaction latencies) of `seconds` after the first action, on 127.0.0.1."""
    port = free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "lerobot.async_inference.policy_server", "--host=127.0.0.1", f"--port={port}",
         f"--fps={fps}", "--inference_latency=0", "--obs_queue_timeout=1"],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    client = None
    try:
        _wait_for_port(port, server)
        config = RobotClientConfig(
            policy_type="act",
            pretrained_name_or_path=str(policy_dir),
            robot=BenchRobotConfig(),
            actions_per_chunk=tiny_act.CHUNK_SIZE,
            server_address=f"127.0.0.1:{port}",
            fps=fps,
        )
        client = WatchedClient(config)
        if not client.start():
            raise RuntimeError("LeRobot's robot client could not reach its policy server")
        receiver = threading.Thread(target=client.receive_actions, daemon=True)
        loop = threading.Thread(target=client.control_loop, kwargs={"task": ""}, daemon=True)
        receiver.start()
        loop.start()
        deadline = time.monotonic() + SERVER_START_TIMEOUT_S
        while not client.executed and time.monotonic() < deadline:
            time.sleep(0.05)
        if not client.executed:
            raise RuntimeError("LeRobot's async inference executed no action")
        time.sleep(warm_up_s)
        start = time.time()
        reactions_before = len(client.reactions)
        time.sleep(seconds)
        end = time.time()
        executed = [t for t in client.executed if start <= t < end]
        return executed, client.reactions[reactions_before:]
    finally:
        if client is not None:
            client.shutdown_event.set()
            client.channel.close()
        server.terminate()
        try:
            server.wait(SERVER_STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()


def _wait_for_port(port: int, server: subprocess.Popen) -> None:
    deadline = time.monotonic() + SERVER_START_TIMEOUT_S
    while time.monotonic() < deadline:
        if server.poll() is not None:
            raise RuntimeError(f"LeRobot's policy server exited with {server.returncode}")
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.5):
                return
        except OSError:
            time.sleep(0.2)
    raise RuntimeError("LeRobot's policy server did not listen in time")
