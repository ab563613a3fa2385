"""A robot built by joshuac reaches the fleet view with the credentials its description names: a password
file, or the certificates of docs/security.md for mutual TLS. Only paths enter the build; the secret stays in its file."""

import json
from contextlib import ExitStack

from dashboard_support import free_port, running_robot
from fleet_support import make_certificates, running_fleet

PASSWORD = "robot-SECRET-password"


def description(robot: str, port: int, credentials: str) -> str:
    return f"""robot_config {{
  name: "{robot}"
  mode: MODE_TELEOPERATION
  node {{ name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" rate_hz: 10 }}
  dashboard {{ port: {port} {credentials} }}
}}
"""


def test_a_robot_with_a_password_file_appears_and_its_password_stays_in_the_file(tmp_path, ros_env):
    users = tmp_path / "fleet-users.txt"
    users.write_text(f"fleet_pw:{PASSWORD}\n")
    password_file = tmp_path / "fleet-password"
    password_file.write_text(PASSWORD + "\n")
    with running_fleet(tmp_path, "--users", str(users)) as fleet, ExitStack() as robots:
        port = free_port()
        credentials = f'zenoh_connect: "{fleet.endpoint}" zenoh_password_file: "{password_file}"'
        robot_dir = tmp_path / "fleet_pw"
        robot_dir.mkdir()
        robots.enter_context(running_robot(description("fleet_pw", port, credentials), robot_dir, ros_env, port))
        entry = fleet.wait_for("fleet_pw")
        assert entry["url"] == f"http://127.0.0.1:{port}/"
        build = robot_dir / "out"
        generated = [path for path in build.rglob("*") if path.is_file()]
        assert any(str(password_file) in path.read_text(errors="replace") for path in generated)
        assert not any(PASSWORD in path.read_text(errors="replace") for path in generated)
        assert PASSWORD not in (robot_dir / "supervisor.log").read_text()
        assert not any(PASSWORD in log.read_text(errors="replace") for log in (robot_dir / "logs").rglob("*"))
        assert PASSWORD not in fleet.log.read_text()
        assert PASSWORD not in json.dumps(fleet.robots())


def test_robots_with_certificates_of_the_fleets_ca_appear(tmp_path, ros_env):
    robots_names = ["fleet_tls_a", "fleet_tls_b"]
    certs = make_certificates(tmp_path / "certs", "IP:127.0.0.1", robots_names)
    (certs / "robots.txt").write_text("\n".join(robots_names) + "\n")
    arguments = ["--tls-certificate", str(certs / "fleet.pem"), "--tls-private-key", str(certs / "fleet.key")]
    arguments += ["--tls-ca", str(certs / "ca.pem"), "--robots", str(certs / "robots.txt")]
    with running_fleet(tmp_path, *arguments, scheme="tls") as fleet, ExitStack() as robots:
        for offset, robot in enumerate(robots_names):
            port = free_port()
            credentials = (
                f'zenoh_connect: "{fleet.endpoint}" zenoh_tls_ca: "{certs / "ca.pem"}" '
                f'zenoh_tls_certificate: "{certs / f"{robot}.pem"}" zenoh_tls_private_key: "{certs / f"{robot}.key"}"'
            )
            env = dict(ros_env, ROS_DOMAIN_ID=str(int(ros_env["ROS_DOMAIN_ID"]) + offset))
            directory = tmp_path / robot
            directory.mkdir()
            robots.enter_context(running_robot(description(robot, port, credentials), directory, env, port))
        for robot in robots_names:
            entry = fleet.wait_for(robot)
            assert [node["name"] for node in entry["nodes"]] == ["leader", "dashboard"]
