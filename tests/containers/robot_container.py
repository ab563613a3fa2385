"""Running a robot's image in the tests: start it in a network namespace, wait for its nodes, peek with a peer, stop it."""

import json
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


def lag_violations(follower: list[dict], leader: list[dict], window_s: float, tolerance: float) -> list[tuple]:
    """Follower positions outside what the leader commanded over the `window_s` before them (± tolerance).

    An arm that follows a moving leader lags it; where it is must lie between the goals it was given lately."""
    violations = []
    for sample in follower:
        recent = [goal["position"] for goal in leader if sample["t"] - window_s <= goal["t"] <= sample["t"]]
        if not recent:
            continue
        for joint, position, goals in zip(sample["name"], sample["position"], zip(*recent)):
            if not min(goals) - tolerance <= position <= max(goals) + tolerance:
                violations.append((joint, position, min(goals), max(goals)))
    return violations
