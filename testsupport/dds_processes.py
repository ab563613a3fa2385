"""DDS processes inside simulated hosts (testsupport/hosts.py): dds_probe programs and a Discovery Server."""

import subprocess
import sys
from pathlib import Path

from testsupport.probe_output import ProbeOutput

ROOT = Path(__file__).resolve().parents[1]  # where `python -m testsupport.dds_probe` is found
SERVER_PORT = 11811  # inside the server host's own namespace: nothing else of the machine can hold it
START_TIMEOUT_S = 60.0  # a cold rclpy process on a busy 2-core machine
DISCOVERY_TIMEOUT_S = 30.0  # discovery that should happen, with room for a loaded machine
ABSENCE_WINDOW_S = 8.0  # how long "never discovered" is watched: several times a working discovery
SERVER_READY_LINE = "Server is running"
SERVER_TYPE_LINE = "Participant Type:   SERVER"


def probe(host, env: dict, mode: str, *args: str) -> ProbeOutput:
    """testsupport/dds_probe.py in `host` (`talk`, `listen` or `graph` with its options); killed with the hosts."""
    process = host.popen(
        [sys.executable, "-m", "testsupport.dds_probe", mode, *args],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    return ProbeOutput(process)


def start_server(host, env: dict, port: int = SERVER_PORT, profile: Path | None = None) -> ProbeOutput:
    """The Discovery Server on `host`'s address, started as the runtime's launcher runs it; waits until it runs."""
    command = [sys.executable, "-m", "joshua_runtime.discovery.server", "--address", host.address, "--port", str(port)]
    if profile is not None:
        command += ["--profile", str(profile)]
    process = host.popen(command, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    server = ProbeOutput(process)
    assert server.wait_for(lambda output: any(SERVER_READY_LINE in line for line in output.lines()), START_TIMEOUT_S), (
        server.tail()
    )
    # A profile without <discoveryProtocol>SERVER</discoveryProtocol> silently makes it a SIMPLE participant.
    assert server.wait_for(lambda output: any(SERVER_TYPE_LINE in line for line in output.lines()), START_TIMEOUT_S), (
        server.tail()
    )
    return server


PROBE_CODE = (
    "import sys; from joshua_runtime.discovery.probe import probe; "
    "r = probe(sys.argv[1], int(sys.argv[2]), *map(int, sys.argv[3:])); print(r.answered, r.detail)"
)


def probe_server_from(host, address: str, *server_id: int, port: int = SERVER_PORT) -> str:
    """What the runtime's Discovery Server probe says, run inside `host`: "True ..." or "False <why>"."""
    command = [sys.executable, "-c", PROBE_CODE, address, str(port), *map(str, server_id)]
    return host.run(command, cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()


def client_env(env: dict, profile: Path) -> dict:
    """`env` with a participant profile (FASTRTPS_DEFAULT_PROFILES_FILE)."""
    return dict(env, FASTRTPS_DEFAULT_PROFILES_FILE=str(profile))


def server_locator(host, port: int = SERVER_PORT) -> str:
    """The ROS_DISCOVERY_SERVER value naming a server with id 0 on `host`."""
    return f"{host.address}:{port}"


def received(listener: ProbeOutput, timeout_s: float = DISCOVERY_TIMEOUT_S, at_least: int = 1) -> bool:
    return listener.wait_for(lambda output: len(output.of("received")) >= at_least, timeout_s)


def ready(*probes: ProbeOutput) -> None:
    for started in probes:
        assert started.wait_for(lambda output: output.of("ready"), START_TIMEOUT_S), started.tail()


def project_profile(directory: Path, images: bool) -> Path:
    """The participant profile `joshuac build` writes today (no Discovery Server), for image nodes or the others."""
    from joshua_codegen.compile import plan_text
    from joshua_codegen.emitters import fastdds
    from joshua_codegen.render import render

    description = (
        'robot_config { name: "multihost" mode: MODE_TELEOPERATION '
        'node { name: "camera" type: MOCK_CAMERA_PUBLISHER topic_name: "/camera/image_raw" } }'
    )
    name = fastdds.IMAGES_PROFILE_PATH if images else fastdds.PROFILE_PATH
    path = directory / name
    path.write_text(render(plan_text(description))[name])
    return path
