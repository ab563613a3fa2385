"""RobotConfig.dashboard: one more process, `dashboard`, under supervisor.py, systemd and supervisord."""

import ast
import json

from google.protobuf import text_format

from joshua_codegen.check import check_text
from joshua_codegen.plan import plan
from joshua_codegen.render import render
from joshua_core.schema import RobotDescription

ROBOT = """robot_config {{ name: "r" mode: MODE_TELEOPERATION
  node {{ name: "{node}" type: MOCK_ENCODER_PUBLISHER topic_name: "/joints" }}
  {dashboard} }}"""


def build(dashboard: str, node: str = "leader") -> dict[str, str]:
    description = text_format.Parse(ROBOT.format(dashboard=dashboard, node=node), RobotDescription())
    return render(plan(description, "r.pbtxt"), None)


def arguments(files: dict[str, str]) -> list[str]:
    """The ARGUMENTS literal of the generated dashboard entrypoint (which must compile)."""
    module = ast.parse(files["nodes/dashboard.py"])
    (value,) = [s.value for s in module.body if isinstance(s, ast.Assign) and s.targets[0].id == "ARGUMENTS"]
    return ast.literal_eval(value)


def test_a_dashboard_block_adds_one_process_to_every_process_manager():
    files = build('dashboard { port: 9000 bind: "0.0.0.0" zenoh_connect: "tcp/10.0.0.5:7447" }')
    assert arguments(files) == ["--port", "9000", "--bind", "0.0.0.0", "--zenoh-connect", "tcp/10.0.0.5:7447"]
    processes = json.loads(files["manifest.json"])["processes"]
    assert [(p["name"], p["type"], p["entrypoint"]) for p in processes] == [
        ("leader", "MOCK_ENCODER_PUBLISHER", "nodes/leader.py"),
        ("dashboard", "DASHBOARD", "nodes/dashboard.py"),
    ]
    assert "systemd/joshua-r-dashboard.service" in files
    assert "[program:dashboard]" in files["supervisord.conf"]
    assert '"name": "dashboard"' in files["supervisor.py"] or "'name': 'dashboard'" in files["supervisor.py"]


def test_an_empty_block_listens_on_loopback_port_8640_without_fleet():
    assert arguments(build("dashboard { }")) == ["--port", "8640", "--bind", "127.0.0.1"]


def test_allowed_host_names_reach_the_dashboard_as_arguments():
    files = build('dashboard { allowed_host: "robot.example.org" allowed_host: "10.0.0.7" }')
    assert arguments(files) == [
        "--port", "8640", "--bind", "127.0.0.1", "--allowed-host", "robot.example.org", "--allowed-host", "10.0.0.7",
    ]  # fmt: skip


def test_without_a_block_there_is_no_dashboard():
    files = build("")
    assert "nodes/dashboard.py" not in files
    assert not any("dashboard" in path for path in files)


def test_the_name_dashboard_is_reserved_when_a_dashboard_runs():
    result = check_text("r.pbtxt", ROBOT.format(dashboard="dashboard { }", node="dashboard"))
    assert [(d.code, d.message) for d in result.diagnostics if d.severity == "error"] == [
        ("E205", 'node name "dashboard" is reserved for the dashboard process')
    ]
    assert not check_text("r.pbtxt", ROBOT.format(dashboard="", node="dashboard")).has_errors


def test_fleet_credentials_reach_the_dashboard_as_paths():
    files = build(
        'dashboard { zenoh_connect: "tls/10.0.0.5:7447" zenoh_password_file: "/etc/joshua/fleet-password" '
        'zenoh_tls_ca: "/etc/joshua/ca.pem" zenoh_tls_certificate: "/etc/joshua/r.pem" '
        'zenoh_tls_private_key: "/etc/joshua/r.key" }'
    )
    assert arguments(files)[4:] == [
        "--zenoh-connect",
        "tls/10.0.0.5:7447",
        "--zenoh-password-file",
        "/etc/joshua/fleet-password",
        "--zenoh-tls-ca",
        "/etc/joshua/ca.pem",
        "--zenoh-tls-certificate",
        "/etc/joshua/r.pem",
        "--zenoh-tls-private-key",
        "/etc/joshua/r.key",
    ]


def test_the_manifest_tells_which_processes_are_critical():
    files = build(
        'dashboard { port: 9000 }\n  node { name: "helper" type: CUSTOM executable: "/bin/true" critical: false }'
    )
    critical = {p["name"]: p["critical"] for p in json.loads(files["manifest.json"])["processes"]}
    assert critical == {"leader": True, "helper": False, "dashboard": False}
