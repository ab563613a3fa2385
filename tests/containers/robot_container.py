"""Running a robot's image in the tests: start it in a network namespace, wait for its nodes, peek with a peer, stop it."""

import json
import statistics
import time
from pathlib import Path

from testsupport.podman import Podman

ROOT = Path(__file__).resolve().parents[2]
PEER_SCRIPT = ROOT / "testsupport" / "container_peer.py"
READY_TIMEOUT_S = 120.0  # every node ready: on a loaded machine MuJoCo alone takes a while to start
POLL_S = 0.5
PEER_TIMEOUT_S = 60.0
STOP_SLACK_S = 30.0  # beyond the image's stop timeout, for podman itself
ROS_VARIABLES = ("-e", "ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST", "-e", "ROS_DOMAIN_ID=0")


def start(podman: Podman, image: str, name: str, *options: str, arguments=()) -> None:
    """Start the image's supervisor in the background as container `name`."""
    podman.run("run", "--detach", "--name", name, *ROS_VARIABLES, *options, image, *arguments)


def logs(podman: Podman, name: str) -> str:
    done = podman.run("logs", name, check=False)
    return done.stdout + done.stderr


def wait_for_log(podman: Podman, name: str, text: str, timeout_s: float = READY_TIMEOUT_S) -> str:
    """The container's log once it holds `text`; fails with the log when it never does or the container ends."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        output = logs(podman, name)
        if text in output:
            return output
        if state(podman, name) == "exited":
            break
        time.sleep(POLL_S)
    raise AssertionError(f"{text!r} not in the log of {name}:\n{logs(podman, name)}")


def state(podman: Podman, name: str) -> str:
    return podman.run("inspect", "--format", "{{.State.Status}}", name).stdout.strip()


def exit_code(podman: Podman, name: str) -> int:
    return int(podman.run("inspect", "--format", "{{.State.ExitCode}}", name).stdout)


def peer_samples(podman: Podman, image: str, robot: str, network: str, topics: list[str], seconds: float) -> dict:
    """What a ROS peer in a second container beside `robot` (its network, its IPC) records on `topics`."""
    done = podman.run(
        "run",
        "--rm",
        network,
        f"--ipc=container:{robot}",
        *ROS_VARIABLES,
        "-v",
        f"{PEER_SCRIPT}:/peer.py:ro",
        "--entrypoint",
        "python3",
        image,
        "/peer.py",
        "--seconds",
        str(seconds),
        *topics,
        timeout=PEER_TIMEOUT_S + seconds,
        check=False,
    )
    assert done.returncode == 0, f"peer exited {done.returncode}: {done.stdout[-2000:]}{done.stderr[-2000:]}"
    return json.loads(done.stdout)


def stop(podman: Podman, name: str, timeout_s: int) -> float:
    """`podman stop -t timeout_s`; the seconds it took."""
    started = time.monotonic()
    podman.run("stop", "--time", str(timeout_s), name, timeout=timeout_s + STOP_SLACK_S)
    return time.monotonic() - started


def median_tracking_errors(
    follower: list[dict], leader: list[dict], window_s: float, clock: str = "t"
) -> dict[str, float]:
    """Per joint, the median over the follower's samples of how far it is from the nearest goal the leader gave
    in the `window_s` before: an arm that follows reaches its goals with a lag, most of the time. Times are the
    peer's receipts (`t`), or the publishers' own stamps (`stamp`) where both stamp with the same clock: a peer
    that falls behind takes in the two topics in bursts, which receipt times would misplace."""
    errors: dict[str, list[float]] = {}
    for sample in follower:
        now = sample[clock]
        recent = [goal["position"] for goal in leader if now - window_s <= goal[clock] <= now]
        if not recent:
            continue
        for joint, position, goals in zip(sample["name"], sample["position"], zip(*recent)):
            errors.setdefault(joint, []).append(min(abs(position - goal) for goal in goals))
    return {joint: statistics.median(values) for joint, values in errors.items()}
