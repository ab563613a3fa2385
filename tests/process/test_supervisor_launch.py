"""What the supervisor starts: preflight, the C++/Python backend rule, the environment, and its options."""

import ast
import json
import os
import shutil
import signal

from supervisor_harness import CPP_STAND_IN, Supervisor, build, custom_node, describe, events, robot, wait_until

from joshua_codegen.plan import plan
from joshua_codegen.version import VERSION


def stand_in(path, body=CPP_STAND_IN):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(body)
    path.chmod(0o755)
    return path


def argv_lines(path):
    return wait_until(lambda: path.exists() and path.read_text().splitlines(), f"{path.name} to be written")


def encoder(tmp_path, serial_port, backend="CPP"):
    return (
        f'node {{ name: "arm" type: ENCODER_PUBLISHER topic_name: "/joints" serial_port: "{serial_port}" '
        f"preferred_backend: {backend} }}"
    )


def test_preflight_lists_every_problem_and_starts_nothing(tmp_path):
    log = tmp_path / "events.log"
    bin_dir = tmp_path / "bin"
    (bin_dir / "encoder_publisher").parent.mkdir()
    (bin_dir / "encoder_publisher").write_text("not executable")
    nodes = [
        encoder(tmp_path, tmp_path / "ttyMISSING"),
        'node { name: "cam" type: CAMERA_PUBLISHER topic_name: "/image" camera_index: 63 }',
        f'node {{ name: "clip" type: CAMERA_PUBLISHER topic_name: "/clip" video_source: "{tmp_path}/none.mp4" }}',
        f'node {{ name: "policy" type: INFERENCE topic_name: "/joints_cmd" input_topics: ["/joints"] '
        f'model_path: "{tmp_path}/no_model" }}',
        'node { name: "tool" type: CUSTOM executable: "joshua-no-such-program" }',
        custom_node("fine", log),
    ]
    out = build(tmp_path, robot(nodes, extra=f'cpp_bin_dir: "{bin_dir}"'))
    supervisor = Supervisor(out, "--python", str(tmp_path / "no-python"))
    try:
        assert supervisor.wait() == 3
    finally:
        supervisor.close()
    text = supervisor.log()
    problems = [line[4:] for line in text.splitlines() if line.startswith("  - ")]
    assert problems == [
        f"arm: serial port {tmp_path}/ttyMISSING does not exist",
        f"arm: C++ binary {bin_dir}/encoder_publisher exists but is not an executable file",
        "cam: camera device /dev/video63 does not exist",
        f"clip: video file {tmp_path}/none.mp4 does not exist",
        f"policy: model directory {tmp_path}/no_model does not exist",
        "tool: program joshua-no-such-program is not an executable file (or not on PATH)",
        f"Python interpreter {tmp_path}/no-python is not an executable file",
    ]
    assert "preflight found 7 problem(s); nothing was started" in text
    assert "started pid" not in text and not log.exists()


def test_skip_preflight_starts_what_can_start(tmp_path):
    log = tmp_path / "events.log"
    nodes = [
        'node { name: "tool" type: CUSTOM executable: "joshua-no-such-program" max_restarts: 0 critical: false }',
        custom_node("fine", log),
    ]
    out = build(tmp_path, robot(nodes))
    supervisor = Supervisor(out, "--skip-preflight")
    try:
        supervisor.wait_log(r"tool: failed for good after 0 restarts")
        wait_until(lambda: events(log), "the fine node to start")
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 5
    finally:
        supervisor.close()
    text = supervisor.log()
    assert "cannot start joshua-no-such-program" in text
    assert "tool: pid" in text and "exited with code 127" in text


def test_an_executable_cpp_binary_runs_with_its_ros_arguments(tmp_path):
    serial = tmp_path / "ttyFAKE"
    serial.write_text("")
    binary = stand_in(tmp_path / "bin" / "encoder_publisher")
    config = robot([encoder(tmp_path, serial)], extra=f'cpp_bin_dir: "{tmp_path / "bin"}"')
    out = build(tmp_path, config)
    supervisor = Supervisor(out)
    try:
        argv = argv_lines(tmp_path / "bin" / "argv.txt")
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 0
    finally:
        supervisor.close()
    [process] = plan(describe(config), "robot.pbtxt").processes
    assert argv == [str(binary), *process.cpp_args]
    assert "arm: started pid" in supervisor.log() and "(C++)" in supervisor.log()
    # A C++ node is ready when it says so (READY=1), like a Python one; this stand-in never does.
    assert "arm: ready" not in supervisor.log()
    assert "warning" not in supervisor.log()


def test_without_the_cpp_binary_the_python_entrypoint_runs_after_one_warning(tmp_path):
    serial = tmp_path / "ttyFAKE"
    serial.write_text("")
    python = stand_in(tmp_path / "fake" / "python")
    out = build(tmp_path, robot([encoder(tmp_path, serial)], extra=f'cpp_bin_dir: "{tmp_path / "bin"}"'))
    supervisor = Supervisor(out, "--python", str(python), "--skip-preflight")  # the stand-in is no interpreter
    try:
        argv = argv_lines(tmp_path / "fake" / "argv.txt")
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 0
    finally:
        supervisor.close()
    assert argv == [str(python), str(out / "nodes" / "arm.py")]
    warnings = [line for line in supervisor.log().splitlines() if "warning" in line]
    assert len(warnings) == 1
    assert warnings[0].endswith(
        f"arm: warning: C++ binary {tmp_path}/bin/encoder_publisher is missing or not "
        "executable; running the Python entrypoint (make cpp in the joshuac repository "
        "builds the binaries into build/bin; set cpp_bin_dir in the description to the "
        "directory holding them)"
    )


def test_nodes_get_the_dds_profile_domain_and_description_environment_even_after_a_move(tmp_path):
    log = tmp_path / "events.log"
    env_file = tmp_path / "env.json"
    node = custom_node("a", log, f"env_file={env_file}")
    node = node[:-1] + ' env { key: "NODE_ONLY" value: "n" } env { key: "SHARED" value: "node wins" } }'
    extra = 'ros_domain_id: 42 env { key: "SHARED" value: "robot" } env { key: "ROBOT_ONLY" value: "$HOME \\"q\\"" }'
    built = build(tmp_path, robot([node], extra=extra))
    moved = tmp_path / "elsewhere" / "robot"
    moved.parent.mkdir()
    shutil.move(built, moved)
    supervisor = Supervisor(moved, env=dict(os.environ, ROS_DOMAIN_ID="7", PYTHONUNBUFFERED="0"))
    try:
        wait_until(lambda: events(log), "the node to start")
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 0
    finally:
        supervisor.close()
    env = json.loads(env_file.read_text())["env"]
    assert env["FASTRTPS_DEFAULT_PROFILES_FILE"] == str(
        moved / "fastdds_profile_images.xml"
    )  # custom: may carry images
    assert (moved / "fastdds_profile_images.xml").is_file()
    assert env["PYTHONUNBUFFERED"] == "1"
    assert env["ROS_DOMAIN_ID"] == "42"
    assert (env["SHARED"], env["NODE_ONLY"], env["ROBOT_ONLY"]) == ("node wins", "n", '$HOME "q"')
    assert env["PATH"] == os.environ["PATH"]


def test_status_interval_prints_one_line_per_node(tmp_path):
    log = tmp_path / "events.log"
    out = build(tmp_path, robot([custom_node("a", log), custom_node("b", log)]))
    supervisor = Supervisor(out, "--status-interval", "0.2")
    try:
        supervisor.wait_log(
            r"supervisor: status: 2 running\n.* a: running pid \d+ for [\d.]+ s, custom, ready, 0 restarts\n"
            r".* b: running pid \d+ for [\d.]+ s, custom, ready, 0 restarts$"
        )
        supervisor.signal(signal.SIGINT)
        assert supervisor.wait() == 0
    finally:
        supervisor.close()
    assert "ready: 2 of 2 nodes ready" in supervisor.log()


def test_bad_command_line_exits_2(tmp_path):
    out = build(tmp_path, robot([custom_node("a", tmp_path / "events.log")]))
    supervisor = Supervisor(out, "--duration", "-1")
    try:
        assert supervisor.wait() == 2
    finally:
        supervisor.close()
    assert "must be a positive number of seconds" in supervisor.log()


def test_generated_supervisor_is_standard_library_python_3_10_with_a_header(tmp_path):
    out = build(tmp_path, robot([custom_node("a", tmp_path / "events.log")]), source="arm.pbtxt")
    text = (out / "supervisor.py").read_text()
    assert text.splitlines()[:2] == [
        "#!/usr/bin/env python3",
        f"# Generated by joshuac {VERSION} from arm.pbtxt. DO NOT EDIT.",
    ]
    imported = set()
    for path in ("supervisor.py", "supervisor_code.py"):
        tree = ast.parse((out / path).read_text(), feature_version=(3, 10))
        imported |= {
            alias.name.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names
        }
        imported |= {node.module.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    assert imported <= {
        "argparse",
        "ast",  # a reload reads a new build's data as literals
        "collections",
        "ctypes",
        "errno",
        "hashlib",
        "importlib",  # supervisor.py checks its code's bytecode: the .pyc magic number and source hash
        "json",
        "marshal",
        "math",
        "os",
        "re",
        "resource",
        "select",
        "selectors",
        "shlex",
        "signal",
        "socket",
        "stat",
        "struct",
        "subprocess",
        "sys",
        "time",
        "traceback",
    }
    assert os.access(out / "supervisor.py", os.X_OK) and not os.access(out / "supervisor_code.py", os.X_OK)
