"""The control plane in the build of a robot on several hosts: an agent on every host, the control host's listening
and the others connecting, each with the paths of its own credentials only, and the rules of `control { }`."""

import ast
import json

import pytest

from joshua_codegen.bundle import extras
from joshua_codegen.check import check_text
from joshua_codegen.diagnostics import format_text
from joshua_codegen.emitters.supervisor import supervisor_data
from joshua_codegen.plan import plan
from joshua_codegen.render import render
from joshua_codegen.supervisor.ctl_hosts import HOSTS_SOCKET_VARIABLE
from joshua_codegen.supervisor.ctl_hosts import hosts_socket_path as supervisor_hosts_socket_path
from joshua_core import control_plane

ROBOT = """
robot_config {{
  name: "split"
  mode: MODE_TELEOPERATION
  host {{ name: "arm" address: "10.0.0.2" }}
  host {{ name: "gpu" address: "10.0.0.3" }}
  host {{ name: "pi" address: "10.0.0.4" }}
  discovery {{ server_host: "arm" }}
  {control}
  node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER host: "pi" topic_name: "/leader/joint_states" }}
  node {{ name: "follower" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states" }}
}}
"""
PASSWORDS = (
    'control { host: "gpu" password_file: "/etc/joshua/control.password" users_file: "/etc/joshua/control-users.txt" }'
)
CERTIFICATES = (
    'control { port: 7500 tls_ca: "/etc/joshua/control-ca.pem" tls_certificate: "/etc/joshua/control.pem" '
    'tls_private_key: "/etc/joshua/control.key" }'
)


def checked(text: str):
    result = check_text("split.pbtxt", text)
    assert not result.has_errors, format_text(result.diagnostics, result.sources)
    return result


def diagnostics(text: str) -> list[tuple[str, str]]:
    result = check_text("split.pbtxt", text)
    return [(d.code, d.message) for d in result.diagnostics]


def files_of(text: str) -> dict[str, str]:
    result = checked(text)
    return render(result.robot or plan(result.description, "split.pbtxt"))


def agent_arguments(files: dict[str, str], host: str) -> list[str]:
    text = files[f"hosts/{host}/nodes/host_agent_{host}.py"]
    line = next(line for line in text.splitlines() if line.startswith("ARGUMENTS = "))
    return ast.literal_eval(line.removeprefix("ARGUMENTS = "))


def test_every_host_runs_an_agent_the_control_hosts_listening_the_others_connecting():
    files = files_of(ROBOT.format(control=PASSWORDS))
    endpoint = "tcp/10.0.0.3:7448"
    assert agent_arguments(files, "gpu") == [
        "--listen",
        endpoint,
        "--password-file",
        "/etc/joshua/control.password",
        "--users-file",
        "/etc/joshua/control-users.txt",
    ]
    for host in ("arm", "pi"):
        assert agent_arguments(files, host) == [
            "--connect",
            endpoint,
            "--password-file",
            "/etc/joshua/control.password",
        ]
        assert "control-users.txt" not in "".join(
            text for path, text in files.items() if path.startswith(f"hosts/{host}/")
        )
    whole = json.loads(files["manifest.json"])
    assert whole["control"] == {"host": "gpu", "endpoint": endpoint}
    assert [h["processes"][-1] for h in whole["hosts"]] == ["host_agent_arm", "host_agent_gpu", "host_agent_pi"]
    assert "systemd/joshua-split-host_agent_pi.service" in {p.removeprefix("hosts/pi/") for p in files}


def test_certificates_make_the_link_tls_and_every_host_gets_the_same_paths():
    files = files_of(ROBOT.format(control=CERTIFICATES))
    tls = ["--tls-ca", "/etc/joshua/control-ca.pem", "--tls-certificate", "/etc/joshua/control.pem"]
    tls += ["--tls-private-key", "/etc/joshua/control.key"]
    assert agent_arguments(files, "arm") == ["--listen", "tls/10.0.0.2:7500", *tls]
    assert agent_arguments(files, "pi") == ["--connect", "tls/10.0.0.2:7500", *tls]


def test_without_control_the_agents_only_watch_the_discovery_server():
    files = files_of(ROBOT.format(control=""))
    assert agent_arguments(files, "arm") == agent_arguments(files, "pi") == []
    assert json.loads(files["manifest.json"])["control"] is None


def test_each_hosts_supervisor_knows_its_hosts_and_the_server_its_agent_watches():
    robot = plan(checked(ROBOT.format(control=PASSWORDS)).description, "split.pbtxt")
    data = supervisor_data(robot.for_host("pi"))
    assert (data["host"], data["hosts"], data["discovery_server"]) == ("pi", ["arm", "gpu", "pi"], "10.0.0.2:11811")
    without_server = ROBOT.format(control="").replace('discovery { server_host: "arm" }', "")
    assert "discovery_server" not in supervisor_data(plan(checked(without_server).description, "x").for_host("pi"))
    # the agent's socket, as supervisor.py and the runtime both derive it
    assert HOSTS_SOCKET_VARIABLE == control_plane.HOSTS_SOCKET_VARIABLE
    for path in ("/run/user/0/joshua/split.pi.sock", "/tmp/joshua-0/odd-name"):
        assert supervisor_hosts_socket_path(path) == control_plane.hosts_socket_path(path)


@pytest.mark.parametrize(
    ("control", "expected"),
    [
        ("control { port: 7500 }", "`control { }` needs credentials: password_file and users_file, or tls_ca"),
        ('control { users_file: "/etc/u.txt" }', "users_file needs password_file"),
        ('control { tls_certificate: "/c.pem" tls_private_key: "/c.key" }', "(missing: tls_ca)"),
        (
            'control { host: "laptop" password_file: "/p" users_file: "/u" }',
            'names host "laptop", which is not declared',
        ),
    ],
)
def test_a_control_block_that_cannot_work_is_an_error(control, expected):
    found = diagnostics(ROBOT.format(control=control))
    assert any(code in ("E146", "E143") and expected in message for code, message in found), found


def test_control_needs_hosts_and_the_agents_names_are_reserved():
    one_computer = 'robot_config { name: "r" mode: MODE_TELEOPERATION control { password_file: "/p" users_file: "/u" }'
    one_computer += ' node { type: MOCK_ENCODER_PUBLISHER topic_name: "/a" } }'
    assert [code for code, _ in diagnostics(one_computer)] == ["E146"]
    taken = ROBOT.format(control="").replace('name: "leader"', 'name: "host_agent_gpu"')
    assert ("E205", 'node name "host_agent_gpu" is reserved for the agent of host "gpu"') in diagnostics(taken)


def test_each_hosts_bundle_installs_zenoh_for_its_agent_with_a_control_plane_and_for_a_dashboard():
    linked = plan(checked(ROBOT.format(control=PASSWORDS)).description, "split.pbtxt")
    assert extras(linked.for_host("pi")) == ["dashboard"]
    alone = plan(checked(ROBOT.format(control="")).description, "split.pbtxt")
    assert extras(alone.for_host("pi")) == []
    with_page = plan(checked(ROBOT.format(control='dashboard { host: "pi" }')).description, "split.pbtxt")
    assert extras(with_page.for_host("pi")) == ["dashboard"]  # the page's server, on the host that runs it
