"""`joshuac check FLEET`: every robot checked with its overrides, each diagnostic where its cause is written."""

import json

from joshua_codegen.check import check_file
from joshua_codegen.diagnostics import format_text
from testsupport.joshuac_cli import joshuac

ARM = """robot_config {
  name: "arm"
  mode: MODE_TELEOPERATION
  node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" }
  node { name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states" }
}
"""
SPLIT = """robot_config {
  name: "split"
  mode: MODE_TELEOPERATION
  host { name: "arm" address: "10.0.0.2" }
  host { name: "pi" address: "10.0.0.4" }
  node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" host: "pi" }
  node { name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states" }
}
"""


def fleet(tmp_path, robots: str, descriptions: dict[str, str] | None = None) -> str:
    (tmp_path / "robots").mkdir(exist_ok=True)
    for name, text in (descriptions or {"arm.pbtxt": ARM}).items():
        (tmp_path / "robots" / name).write_text(text)
    path = tmp_path / "lab.pbtxt"
    path.write_text('# The lab.\nfleet_config {\n  name: "lab"\n' + robots + "}\n")
    return str(path)


def located(result) -> list[tuple[str, int, int, str]]:
    return [(d.path.rsplit("/", 1)[-1], d.line, d.column, d.code) for d in result.diagnostics]


def test_each_robot_is_its_description_with_its_name_overrides_and_the_release_environment(tmp_path):
    path = fleet(
        tmp_path,
        '  robot { name: "arm_1" description: "robots/arm.pbtxt" address: "10.0.0.11"\n'
        '          set: "ros_domain_id=11" set: "leader.rate_hz=25" }\n'
        '  robot { name: "arm_2" description: "robots/arm.pbtxt" address: "10.0.0.12" set: "ros_domain_id=12"\n'
        '          set: "python_executable=/usr/bin/python3" }\n',
    )
    result = check_file(path)
    assert not result.has_errors, format_text(result.diagnostics, result.sources)
    first, second = (member.config for member in result.members)
    assert (first.name, first.ros_domain_id, first.node[0].rate_hz) == ("arm_1", 11, 25)
    assert first.python_executable == "/opt/joshua/current/venv/bin/python3"
    assert (second.name, second.python_executable) == ("arm_2", "/usr/bin/python3")


def test_a_problem_of_an_override_points_at_its_set_line_and_one_of_a_shared_description_is_shown_once(tmp_path):
    broken = ARM.replace('topic_name: "/leader/joint_states" }\n}', 'topic_name: "leader joint states" }\n}')
    path = fleet(
        tmp_path,
        '  robot { name: "arm_1" description: "robots/arm.pbtxt" address: "10.0.0.11" set: "ros_domain_id=11" }\n'
        '  robot { name: "arm_2" description: "robots/arm.pbtxt" address: "10.0.0.12"\n'
        '          set: "ros_domain_id=12" set: "leader.qos_depth=deep" }\n',
        {"arm.pbtxt": broken},
    )
    result = check_file(path)
    assert located(result) == [("lab.pbtxt", 6, 40, "E012"), ("arm.pbtxt", 5, 58, "E203")]
    shared = result.diagnostics[1]
    assert [(note.path.rsplit("/", 1)[-1], note.line, note.message) for note in shared.related] == [
        ("lab.pbtxt", 4, "met checking robot arm_1"),
        ("lab.pbtxt", 5, "met checking robot arm_2"),
    ]
    text = format_text(result.diagnostics, result.sources)
    assert 'set: "ros_domain_id=12" set: "leader.qos_depth=deep" }' in text  # the fleet line, echoed
    assert "qos_depth takes" in result.diagnostics[0].message


def test_an_unreadable_description_is_reported_at_the_robot_that_names_it(tmp_path):
    path = fleet(
        tmp_path,
        '  robot { name: "arm_1" description: "robots/missing.pbtxt" address: "10.0.0.11" }\n',
    )
    result = check_file(path)
    assert located(result) == [("lab.pbtxt", 4, 25, "E007")]
    assert result.diagnostics[0].message.startswith("robots/missing.pbtxt: cannot read the file")


def test_the_hosts_of_a_robot_on_several_computers_get_the_fleets_addresses(tmp_path):
    path = fleet(
        tmp_path,
        '  robot { name: "split_1" description: "robots/split.pbtxt" set: "ros_domain_id=11"\n'
        '          host { name: "pi" address: "10.0.1.4" } }\n'
        '  robot { name: "split_2" description: "robots/split.pbtxt" set: "ros_domain_id=12"\n'
        '          host { name: "arm" address: "10.0.2.2" } host { name: "gpu" address: "10.0.2.3" }\n'
        '          host { name: "pi" address: "10.0.1.4" } }\n',
        {"split.pbtxt": SPLIT},
    )
    result = check_file(path)
    assert located(result) == [("lab.pbtxt", 7, 52, "E011"), ("lab.pbtxt", 8, 11, "E603")]
    assert result.diagnostics[0].message == 'no host named "gpu" (hosts: arm, pi)'
    assert result.diagnostics[1].message == 'address "10.0.1.4" is given to robot split_1 already'
    first = result.members[0].config
    assert [(host.name, host.address) for host in first.host] == [("arm", "10.0.0.2"), ("pi", "10.0.1.4")]


def test_check_takes_fleet_files_on_the_command_line(tmp_path):
    good = fleet(tmp_path, '  robot { name: "arm_1" description: "robots/arm.pbtxt" address: "10.0.0.11" }\n')
    done = joshuac("check", good)
    assert (done.returncode, done.stdout) == (0, "")
    (tmp_path / "bad.pbtxt").write_text('fleet_config {\n  name: "lab"\n  robot { name: "arm_1" addres: "x" }\n}\n')
    done = joshuac("check", str(tmp_path / "bad.pbtxt"), "--format", "json")
    assert done.returncode == 1
    [diagnostic] = json.loads(done.stdout)["diagnostics"]
    assert (diagnostic["line"], diagnostic["column"], diagnostic["code"]) == (3, 25, "E002")
    assert diagnostic["message"] == 'unknown field "addres" in FleetRobot; did you mean "address"?'


def test_fmt_gives_a_fleet_file_the_fleet_schema_header(tmp_path):
    path = fleet(tmp_path, '  robot { name: "arm_1" description: "robots/arm.pbtxt" address: "10.0.0.11" }\n')
    done = joshuac("fmt", path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[:4] == [
        "# proto-file: joshua/v1/fleet_config.proto",
        "# proto-message: joshua.v1.FleetDescription",
        "# The lab.",
        "fleet_config {",
    ]
    (tmp_path / "formatted.pbtxt").write_text(done.stdout)
    assert not check_file(str(tmp_path / "formatted.pbtxt")).has_errors
