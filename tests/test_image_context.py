"""`joshuac build --image`: the Containerfile, the build context and the bundle it installs, without building."""

import subprocess
from pathlib import Path

from joshua_codegen.bundle import extras
from joshua_codegen.compile import plan_text
from testsupport.joshuac_cli import ROOT, joshuac

STAMP = ".joshuac-stamp"


def robot(name: str, *overrides: str):
    path = ROOT / "config" / "robots" / f"{name}.pbtxt"
    return plan_text(path.read_text(), overrides, path.name)


def test_a_robot_with_a_dashboard_installs_the_dashboard_extra():
    """Starlette, uvicorn and Zenoh come with the `dashboard` extra: without it the dashboard exits at start."""
    assert extras(robot("so100_sim")) == ["dashboard", "sim"]
    assert extras(robot("mock_arm")) == []


def build_image_context(tmp_path, name: str, *arguments: str) -> Path:
    out = tmp_path / name
    done = joshuac("build", ROOT / "config" / "robots" / f"{name}.pbtxt", "-o", out, "--image", *arguments)
    assert done.returncode == 0, done.stderr
    return out


def stamped_paths(out: Path) -> list[str]:
    lines = (out / STAMP).read_text().splitlines()
    return sorted(line.split("  ", 1)[1] for line in lines if not line.startswith("#"))  # "# joshuac VERSION" first


def test_the_image_context_is_the_build_its_bundle_and_a_multi_stage_containerfile(tmp_path):
    out = build_image_context(tmp_path, "so100_sim")
    containerfile = (out / "Containerfile").read_text()
    assert "\nARG BASE=debian:bookworm-slim\n" in containerfile
    # One stage from the base, the robot's, which the image is: the environment is installed where it runs.
    assert "\nFROM ${BASE} AS robot\n" in containerfile and containerfile.count("FROM ${BASE}") == 1
    assert containerfile.count("\nFROM robot\n") == 1
    assert "\nFROM robot AS cpp\n" not in containerfile  # the simulation runs no C++ node
    assert not [line for line in containerfile.splitlines() if line.startswith("COPY") and "/opt/joshua/venv" in line]
    assert "RUN JOSHUA_INSTALLER=pip sh /opt/joshua/so100_sim/install.sh /opt/joshua/venv --no-index" in containerfile
    assert 'LABEL io.joshua.robot="so100_sim" io.joshua.stop-timeout="7"' in containerfile  # 3 s + 1 s + 3 s
    assert "\nSTOPSIGNAL SIGINT\n" in containerfile
    assert containerfile.endswith(
        '\nENTRYPOINT ["/usr/bin/catatonit", "--", "/opt/joshua/venv/bin/python3", "-S", "/opt/joshua/so100_sim/supervisor.py"]\n'
    )
    robot_stage, final = containerfile.split("\nFROM robot\n")
    assert (
        "for package in python3 catatonit libegl1 libegl-mesa0 libgl1-mesa-dri libgles2 libgl1 python3-venv;"
        in robot_stage
    )
    assert "JOSHUA_WEB_DIR=/opt/joshua/so100_sim/web" in final
    assert (out / "web" / "index.html").read_bytes() == (ROOT / "web" / "dist" / "index.html").read_bytes()
    # The build context is exactly what the stamp lists, so install.sh finds every file it checks.
    ignore = (out / ".containerignore").read_text().splitlines()
    assert ignore[ignore.index("*") + 1 :] == [f"!{path}" for path in sorted([*stamped_paths(out), STAMP])]
    assert subprocess.run(["sha256sum", "--quiet", "-c", STAMP], cwd=out).returncode == 0


def test_a_robot_with_cpp_nodes_compiles_them_in_a_stage_of_their_own(tmp_path):
    out = build_image_context(tmp_path, "so100_leader_follower")
    containerfile = (out / "Containerfile").read_text()
    robot_stage, cpp_and_final = containerfile.split("\nFROM robot AS cpp\n")
    cpp, final = cpp_and_final.split("\nFROM robot\n")
    assert "g++" not in robot_stage and "g++ make nlohmann-json3-dev libpython3.11-dev" in cpp and "g++" not in final
    assert (
        "RUN make -C /opt/joshua/so100_leader_follower/cpp -j2 VENV=/opt/joshua/venv BUILD=/tmp/joshua/build "
        "/tmp/joshua/build/bin/actuator_subscriber /tmp/joshua/build/bin/encoder_publisher\n"
    ) in cpp  # the camera has no C++ binary: it runs its Python node
    assert (
        'COPY --from=cpp ["/tmp/joshua/build/bin/actuator_subscriber", "/opt/joshua/bin/actuator_subscriber"]' in final
    )
    assert "for package in python3 catatonit libpython3.11 python3-venv;" in robot_stage
    assert (out / "cpp" / "Makefile").read_bytes() == (ROOT / "cpp" / "Makefile").read_bytes()
    assert (out / "cpp" / "nodes" / "actuator_subscriber.cpp").is_file()
    # What the robot needs from the host, in the header's run command and its list.
    assert (
        "#   podman run --rm --stop-timeout 10 --device /dev/ttyUSB0 --device /dev/ttyUSB1 --device /dev/video0 "
        "-v DIR:/data/episodes localhost/joshua/so100_leader_follower [SUPERVISOR OPTIONS]\n"
    ) in containerfile
    assert "#   --device /dev/ttyUSB1    serial of node actuator_subscriber\n" in containerfile


def test_a_prefix_a_containerfile_cannot_hold_is_refused_with_one_line(tmp_path):
    out = tmp_path / "out"
    done = joshuac(
        "build", ROOT / "config" / "robots" / "mock_arm.pbtxt", "-o", out, "--image", "--prefix", "/opt/my robot"
    )
    assert done.returncode == 1
    assert done.stderr == (
        "joshuac: error: --prefix '/opt/my robot' cannot be written in a Containerfile: "
        "use letters, digits and . _ + @ - / only\n"
    )
    assert not out.exists()


def test_make_image_without_podman_or_docker_says_which_to_install(tmp_path):
    context = tmp_path / "context"
    done = subprocess.run(
        ["/usr/bin/make", "--no-print-directory", "-o", "setup", "image", f"CONTEXT={context}"],
        cwd=ROOT,
        env={"HOME": str(tmp_path), "PATH": str(tmp_path)},  # no engine on PATH
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 2, done.stdout + done.stderr  # make's own code for a failed recipe
    assert (
        "make image: neither podman nor docker is installed; install one: podman (Debian and Ubuntu: apt install "
        "podman runc catatonit; `make setup` does) or Docker Engine with BuildKit (docker build --secret)\n"
    ) in done.stderr
    assert "Error 3" in done.stderr and not context.exists()


def test_a_robot_on_several_computers_is_refused_with_one_line(tmp_path):
    source = tmp_path / "split.pbtxt"
    source.write_text(
        'robot_config { name: "split" mode: MODE_TELEOPERATION host { name: "arm" address: "10.0.0.2" } '
        'host { name: "bench" address: "10.0.0.3" } '
        'node { name: "leader" type: MOCK_ENCODER_PUBLISHER host: "bench" topic_name: "/leader/joint_states" } '
        'node { name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states" } }\n'
    )
    out = tmp_path / "out"
    done = joshuac("build", source, "-o", out, "--image")
    assert done.returncode == 1, done.stderr
    assert done.stderr == (
        "joshuac: error: --image makes one container of the whole robot, and this robot runs on several computers "
        "(host blocks): build an image of a description without them\n"
    )
    assert not out.exists()
