"""LeRobot's own async inference (policy_server + RobotClient) on the bench's data, measured like the ROS setups.

The policy server is LeRobot's, started as its own process (`policy_server_command`), on this host or
another. The client side runs as a process too, so it can sit on the robot's host:

    python -m support.lerobot_async SPEC_JSON       (from bench/)

SPEC_JSON gives the server's address and port, the policy directory, the rate, the measurement and
warm-up seconds, and the chunks to measure at least ("min_calls": the measurement goes on past its seconds
until that many came). It waits for the server to listen, starts LeRobot's RobotClient with a robot made for
the bench (support/benchrobot.py: the same camera picture and joint state the ROS setups publish, from
testsupport/tiny_act.py; its `send_action` is the actuator), and prints one JSON line
{"commands", "seconds", "latencies_s"}: actions executed in the measurement and, for each chunk, the time
from its observation (TimedObservation timestamp) to the first action executed from it. The RobotClient
is LeRobot's own, only watched. LeRobot writes its logs/ into the working directory.
"""

import json
import socket
import sys
import threading
import time

from testsupport import tiny_act

SERVER_START_TIMEOUT_S = 120.0
CONNECT_POLL_S = 0.2
POLL_S = 0.05


def policy_server_command(python: str, address: str, port: int, fps: int) -> list[str]:
    return [
        python, "-m", "lerobot.async_inference.policy_server", f"--host={address}", f"--port={port}",
        f"--fps={fps}", "--inference_latency=0", "--obs_queue_timeout=1",
    ]  # fmt: skip


def watched_client_class():
    """LeRobot's RobotClient, noting for each executed action when it ran and the observation it came from."""
    from lerobot.async_inference.robot_client import RobotClient

    class WatchedClient(RobotClient):
        def __init__(self, config):
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

    return WatchedClient


def wait_for_server(address: str, port: int) -> None:
    deadline = time.monotonic() + SERVER_START_TIMEOUT_S
    while time.monotonic() < deadline:
        try:
            with socket.create_connection((address, port), timeout=1.0):
                return
        except OSError:
            time.sleep(CONNECT_POLL_S)
    raise RuntimeError(f"LeRobot's policy server did not listen on {address}:{port} in time")


def measure(spec: dict) -> dict:
    """Run LeRobot's client against the server of `spec`; its figures (see the module's docstring)."""
    from lerobot.async_inference.configs import RobotClientConfig

    from support.benchrobot import BenchRobotConfig

    wait_for_server(spec["address"], spec["port"])
    config = RobotClientConfig(
        policy_type="act",
        pretrained_name_or_path=spec["policy_dir"],
        robot=BenchRobotConfig(),
        actions_per_chunk=tiny_act.CHUNK_SIZE,
        server_address=f"{spec['address']}:{spec['port']}",
        fps=spec["fps"],
    )
    client = watched_client_class()(config)
    if not client.start():
        return {"error": "LeRobot's robot client could not reach its policy server"}
    try:
        threading.Thread(target=client.receive_actions, daemon=True).start()
        threading.Thread(target=client.control_loop, kwargs={"task": ""}, daemon=True).start()
        deadline = time.monotonic() + spec["first_command_timeout_s"]
        while not client.executed:
            if time.monotonic() > deadline:
                return {"error": "LeRobot's async inference executed no action"}
            time.sleep(POLL_S)
        time.sleep(spec["warm_up_s"])
        start, reactions_before = time.time(), len(client.reactions)
        time.sleep(spec["seconds"])
        deadline = time.monotonic() + spec["first_command_timeout_s"]
        while len(client.reactions) - reactions_before < spec.get("min_calls", 0) and time.monotonic() < deadline:
            time.sleep(POLL_S)
        end = time.time()
        executed = [t for t in list(client.executed) if start <= t < end]
        return {"commands": len(executed), "seconds": end - start, "latencies_s": client.reactions[reactions_before:]}
    finally:
        client.shutdown_event.set()
        client.channel.close()


def main() -> int:
    print(json.dumps(measure(json.loads(sys.argv[1]))), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
