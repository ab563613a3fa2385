"""Reading a build as data and planning a reload: which processes restart, start, stop or keep running, and why."""

import ast
import hashlib
from pathlib import Path
from types import SimpleNamespace

import pytest
from google.protobuf import text_format

from joshua_codegen.plan import plan
from joshua_codegen.render import render
from joshua_codegen.supervisor import build as build_module
from joshua_codegen.supervisor.build import BUILD_DATA_NAMES, BuildError, build_data, read_build
from joshua_codegen.supervisor.reload_plan import build_refusal, input_marks, plan_reload
from joshua_codegen.write import write_tree
from joshua_core.schema import RobotDescription

PACKAGE_DIR = Path(build_module.__file__).parent


def description(nodes: str, extra: str = "") -> str:
    return f'robot_config {{ name: "r" mode: MODE_TELEOPERATION {extra}\n{nodes}\n}}'


ARM = 'node { name: "arm" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/arm" rate_hz: 50 }'
CAMERA = 'node { name: "camera" type: MOCK_CAMERA_PUBLISHER topic_name: "/camera" }'
ENCODER = 'node { name: "encoder" type: ENCODER_PUBLISHER topic_name: "/joints" serial_port: "/dev/ttyX" }'
ENCODER_CPP = ENCODER.replace("}", "preferred_backend: CPP }")


def built(tmp_path: Path, name: str, text: str):
    out = tmp_path / name
    write_tree(render(plan(text_format.Parse(text, RobotDescription()), "r.pbtxt")), out)
    return read_build(str(out))


def running(build):
    """The nodes of a robot running `build` as plan_reload sees them."""
    return [SimpleNamespace(name=spec["name"], spec=spec, input_marks={}) for spec in build.robot["processes"]]


def test_the_data_names_are_those_of_the_placeholder_robot_module():
    tree = ast.parse((PACKAGE_DIR / "robot.py").read_text())
    assigned = [node.targets[0].id for node in tree.body if isinstance(node, ast.Assign)]
    annotated = [node.target.id for node in tree.body if isinstance(node, ast.AnnAssign)]
    assert sorted(BUILD_DATA_NAMES) == sorted(assigned + annotated)


def test_a_changed_setting_restarts_only_its_node(tmp_path):
    old = built(tmp_path, "v1", description(f"{ARM}\n{CAMERA}"))
    new = built(tmp_path, "v2", description(f"{ARM.replace('50', '60')}\n{CAMERA}"))
    reload = plan_reload(old, running(old), new)
    assert reload.restart == {"arm": "settings"}
    assert (reload.start, reload.stop, reload.update, reload.keep) == ([], [], {}, ["camera"])


def test_a_new_domain_id_restarts_every_node_for_its_environment(tmp_path):
    old = built(tmp_path, "v1", description(f"{ARM}\n{CAMERA}"))
    new = built(tmp_path, "v2", description(f"{ARM}\n{CAMERA}", "ros_domain_id: 7"))
    assert plan_reload(old, running(old), new).restart == {"arm": "environment", "camera": "environment"}


def test_a_new_restart_policy_is_taken_over_without_a_restart(tmp_path):
    old = built(tmp_path, "v1", description(f"{ARM}\n{CAMERA}"))
    new = built(
        tmp_path, "v2", description(f"{ARM.replace('}', 'restart: RESTART_ALWAYS max_restarts: 9 }')}\n{CAMERA}")
    )
    reload = plan_reload(old, running(old), new)
    assert (reload.restart, reload.update, reload.keep) == ({}, {"arm": "max_restarts, restart"}, ["camera"])


def test_a_new_cpp_bin_dir_restarts_only_the_nodes_with_a_binary(tmp_path):
    old = built(tmp_path, "v1", description(f"{ENCODER_CPP}\n{CAMERA}"))
    new = built(tmp_path, "v2", description(f"{ENCODER_CPP}\n{CAMERA}", 'cpp_bin_dir: "/elsewhere"'))
    reload = plan_reload(old, running(old), new)
    assert (reload.restart, reload.keep) == ({"encoder": "command line"}, ["camera"])


def test_added_and_removed_nodes_start_and_stop(tmp_path):
    old = built(tmp_path, "v1", description(f"{ARM}\n{CAMERA}"))
    new = built(tmp_path, "v2", description(f"{ARM}\n{ENCODER}"))
    reload = plan_reload(old, running(old), new)
    assert (reload.start, reload.stop, reload.keep) == (["encoder"], ["camera"], ["arm"])


def test_a_calibration_file_is_an_input_of_the_node_reading_it_and_a_change_of_it_restarts_it(tmp_path):
    calibration = tmp_path / "arm.json"
    calibration.write_text("{}")
    reading = ENCODER.replace("}", f'calibration_file: "{calibration}" }}')
    old = built(tmp_path, "v1", description(f"{reading}\n{CAMERA}"))
    assert [spec["inputs"] for spec in old.robot["processes"]] == [[str(calibration)], []]
    nodes = running(old)
    nodes[0].input_marks = input_marks([str(calibration)])
    assert plan_reload(old, nodes, old).keep == ["encoder", "camera"]
    calibration.write_text('{"shoulder_pan": {}}')
    assert plan_reload(old, nodes, old).restart == {"encoder": f"{calibration} changed"}


def test_a_calibration_node_writes_its_file_so_it_is_nobodys_input(tmp_path):
    path = tmp_path / "arm.json"
    calibrating = (
        f'node {{ name: "calibration" type: OPERATIONAL_LIMIT_CALIBRATION serial_port: "/dev/ttyX" '
        f'calibration_file: "{path}" }}'
    )
    reading = ENCODER.replace("}", f'calibration_file: "{path}" }}').replace("/dev/ttyX", "/dev/ttyY")
    build = built(tmp_path, "v1", description(f"{calibrating}\n{reading}"))
    assert [spec["inputs"] for spec in build.robot["processes"]] == [[], []]


@pytest.mark.parametrize(
    ("other", "refusal"),
    [
        ({"name": "other"}, "a build of robot 'other', not of robot 'r'"),
        ({"host": "pi"}, "a build of robot 'r' (host 'pi'), not of robot 'r'"),
        (
            {"supervisor_code": "0123456789abcdef"},
            "built by another joshuac (supervisor code 0123456789abcdef, this one runs CODE): restart the robot "
            "from it instead",
        ),
        (
            {"settings_format_version": 99},
            "its settings_format_version differs from the running build's: restart the robot from it instead",
        ),
        ({"env": {"ROS_DOMAIN_ID": "7"}, "cpp_bin_dir": "/elsewhere"}, None),
    ],
)
def test_only_a_build_of_the_same_robot_and_supervisor_code_is_taken(tmp_path, other, refusal):
    old = built(tmp_path, "v1", description(ARM))
    new = SimpleNamespace(robot={**old.robot, **other})
    expected = refusal.replace("CODE", old.robot["supervisor_code"]) if refusal else None
    assert build_refusal(old, new) == expected


def test_supervisor_data_is_read_without_running_anything(tmp_path):
    marker = tmp_path / "ran"
    source = (
        f"import pathlib\npathlib.Path({str(marker)!r}).touch()\n"
        "ROBOT = {'name': 'r', 'processes': []}\nSIGINT_GRACE_S = 1.0\nSIGTERM_GRACE_S = 2.0\n"
    )
    assert build_data(source.encode()) == {
        "ROBOT": {"name": "r", "processes": []},
        "SIGINT_GRACE_S": 1.0,
        "SIGTERM_GRACE_S": 2.0,
    }
    assert not marker.exists()
    with pytest.raises(BuildError, match="^ROBOT in supervisor.py is not plain data$"):
        build_data(b"ROBOT = __import__('os').getcwd()\nSIGINT_GRACE_S = 1\nSIGTERM_GRACE_S = 1\n")
    with pytest.raises(BuildError, match="^supervisor.py holds no SIGTERM_GRACE_S: not a robot's supervisor$"):
        build_data(b"ROBOT = {}\nSIGINT_GRACE_S = 1\n")


def test_one_hosts_part_is_a_build_of_its_own_and_another_hosts_part_is_refused(tmp_path):
    hosts = 'host { name: "arm" address: "127.0.0.1" } host { name: "station" address: "127.0.0.2" }'
    arm_on, camera_on = ARM.replace("}", 'host: "arm" }'), CAMERA.replace("}", 'host: "station" }')
    nodes = f"{arm_on}\n{camera_on}"
    files = render(plan(text_format.Parse(description(nodes, hosts), RobotDescription()), "r.pbtxt"))
    out = tmp_path / "out"
    write_tree(files, out)
    arm, station = read_build(str(out / "hosts" / "arm")), read_build(str(out / "hosts" / "station"))
    assert arm.digest == hashlib.sha256((out / "hosts" / "arm" / ".joshuac-stamp").read_bytes()).hexdigest()
    assert [spec["name"] for spec in arm.robot["processes"]] == ["arm", "host_agent_arm"]
    assert arm.files["nodes/arm.py"] == hashlib.sha256(files["hosts/arm/nodes/arm.py"].encode()).hexdigest()
    assert build_refusal(arm, arm) is None
    assert build_refusal(arm, station) == "a build of robot 'r' (host 'station'), not of robot 'r' (host 'arm')"
