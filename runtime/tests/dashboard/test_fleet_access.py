"""Who may publish to the fleet view: Zenoh's own authentication (user/password, mutual TLS) and access
control, with real Zenoh sessions on loopback. A robot writes only under `joshua/<its name>/`."""

import time

import pytest
from fleet_support import (
    linked_to_fleet,
    make_certificates,
    run_fleet,
    running_fleet,
    status,
    wait_linked,
    zenoh_peer,
)

pytestmark = pytest.mark.process  # joshua-fleet

PASSWORDS = {"arm_1": "first-SECRET-pw", "arm_2": "second-SECRET-pw"}
READ_WAIT_S = 1.0


@pytest.fixture
def users_file(tmp_path):
    path = tmp_path / "fleet-users.txt"
    path.write_text("".join(f"{robot}:{password}\n" for robot, password in PASSWORDS.items()))
    path.chmod(0o600)
    return path


@pytest.fixture
def certificates(tmp_path):
    """The certificates of docs/security.md for a fleet at 127.0.0.1 and robots arm_1, arm_2, and a file naming them."""
    directory = make_certificates(tmp_path / "certs", "IP:127.0.0.1", ["arm_1", "arm_2"])
    (directory / "robots.txt").write_text("# robots of the fleet\narm_1\narm_2\n")
    return directory


def tls_arguments(certs) -> list[str]:
    return [
        "--tls-certificate",
        str(certs / "fleet.pem"),
        "--tls-private-key",
        str(certs / "fleet.key"),
        "--tls-ca",
        str(certs / "ca.pem"),
        "--robots",
        str(certs / "robots.txt"),
    ]


def robot_tls(certs, robot: str | None, ca=None) -> dict:
    """A peer's TLS settings: the fleet's CA, and robot's certificate when given (then TLS is mutual)."""
    settings = {"root_ca_certificate": str(ca or certs / "ca.pem")}
    if robot:
        settings |= {
            "connect_certificate": str(certs / f"{robot}.pem"),
            "connect_private_key": str(certs / f"{robot}.key"),
            "enable_mtls": True,
        }
    return settings


def test_a_peer_without_the_right_password_is_refused(tmp_path, users_file):
    with running_fleet(tmp_path, "--users", str(users_file)) as fleet:
        with (
            zenoh_peer(fleet.endpoint) as anonymous,
            zenoh_peer(fleet.endpoint, "arm_2", "not-the-password") as wrong,
            zenoh_peer(fleet.endpoint, "intruder", "any") as unknown,
            zenoh_peer(fleet.endpoint, "arm_1", PASSWORDS["arm_1"]) as robot,
        ):
            wait_linked(robot)
            anonymous.put("joshua/fake/status", status("fake"))
            wrong.put("joshua/arm_2/status", status("arm_2"))
            unknown.put("joshua/intruder/status", status("intruder"))
            robot.put("joshua/arm_1/status", status("arm_1"))
            fleet.wait_for("arm_1")
            assert not linked_to_fleet(anonymous)
            assert not linked_to_fleet(wrong)
            assert not linked_to_fleet(unknown)
        assert fleet.names() == {"arm_1"}
        assert not any(password in fleet.log.read_text() for password in PASSWORDS.values())


def test_a_robot_with_credentials_cannot_write_another_robots_keys(tmp_path, users_file):
    with running_fleet(tmp_path, "--users", str(users_file)) as fleet:
        with zenoh_peer(fleet.endpoint, "arm_1", PASSWORDS["arm_1"]) as arm_1:
            wait_linked(arm_1)
            arm_1.put("joshua/arm_2/status", status("arm_2", nodes=[("forged", "running")]))
            arm_1.put("joshua/impostor/status", status("impostor"))
            arm_1.put("joshua/arm_1/status", status("arm_1"))
            entry = fleet.wait_for("arm_1")  # the same link keeps order: the puts before it were handled
        assert fleet.names() == {"arm_1"}
        assert [node["name"] for node in entry["nodes"]] == ["leader"]


def test_a_robot_withdraws_its_own_status_but_not_another_robots(tmp_path, users_file):
    with running_fleet(tmp_path, "--users", str(users_file)) as fleet:
        with (
            zenoh_peer(fleet.endpoint, "arm_1", PASSWORDS["arm_1"]) as arm_1,
            zenoh_peer(fleet.endpoint, "arm_2", PASSWORDS["arm_2"]) as arm_2,
        ):
            wait_linked(arm_1)
            wait_linked(arm_2)
            arm_1.put("joshua/arm_1/status", status("arm_1"))
            arm_2.put("joshua/arm_2/status", status("arm_2"))
            fleet.wait_until(lambda robots: [robot["online"] for robot in robots] == [True, True])
            arm_1.delete("joshua/arm_2/status")
            arm_1.delete("joshua/arm_1/status")
            # The same link keeps order: once arm_1 is offline, its delete of arm_2's key was handled.
            listed = fleet.wait_until(lambda robots: not robots[0]["online"])
        assert [(robot["name"], robot["online"]) for robot in listed] == [("arm_1", False), ("arm_2", True)]


def test_a_robot_cannot_read_what_another_robot_publishes(tmp_path, users_file):
    received = []
    with running_fleet(tmp_path, "--users", str(users_file)) as fleet:
        with (
            zenoh_peer(fleet.endpoint, "arm_1", PASSWORDS["arm_1"]) as arm_1,
            zenoh_peer(fleet.endpoint, "arm_2", PASSWORDS["arm_2"]) as arm_2,
        ):
            arm_1.declare_subscriber("joshua/**", received.append)
            wait_linked(arm_1)
            wait_linked(arm_2)
            time.sleep(READ_WAIT_S)  # time for a subscription to reach the fleet, were it allowed
            arm_2.put("joshua/arm_2/status", status("arm_2"))
            fleet.wait_for("arm_2")
            time.sleep(READ_WAIT_S)
    assert received == []


def test_mutual_tls_admits_only_certificates_of_the_fleets_ca_each_for_its_own_keys(tmp_path, certificates):
    rogue = make_certificates(tmp_path / "rogue", "IP:127.0.0.1", ["arm_2"])
    with running_fleet(tmp_path, *tls_arguments(certificates), scheme="tls") as fleet:
        with (
            zenoh_peer(fleet.endpoint, tls=robot_tls(certificates, None)) as no_certificate,
            zenoh_peer(fleet.endpoint, tls=robot_tls(rogue, "arm_2", ca=certificates / "ca.pem")) as other_ca,
            zenoh_peer(fleet.endpoint, tls=robot_tls(certificates, "arm_1")) as arm_1,
        ):
            wait_linked(arm_1)
            no_certificate.put("joshua/fake/status", status("fake"))
            other_ca.put("joshua/arm_2/status", status("arm_2"))
            arm_1.put("joshua/arm_2/status", status("arm_2"))
            arm_1.put("joshua/arm_1/status", status("arm_1"))
            fleet.wait_for("arm_1")
            assert not linked_to_fleet(no_certificate)
            assert not linked_to_fleet(other_ca)
        assert fleet.names() == {"arm_1"}


def test_tls_one_way_with_passwords_admits_only_robots_with_their_password(tmp_path, certificates, users_file):
    arguments = ["--users", str(users_file), *tls_arguments(certificates)[:4]]  # TLS one way, passwords
    with running_fleet(tmp_path, *arguments, scheme="tls") as fleet:
        with (
            zenoh_peer(fleet.endpoint, tls=robot_tls(certificates, None)) as no_password,
            zenoh_peer(fleet.endpoint, "arm_1", PASSWORDS["arm_1"], tls=robot_tls(certificates, None)) as arm_1,
        ):
            wait_linked(arm_1)
            no_password.put("joshua/fake/status", status("fake"))
            arm_1.put("joshua/arm_1/status", status("arm_1"))
            fleet.wait_for("arm_1")
            assert not linked_to_fleet(no_password)
        assert fleet.names() == {"arm_1"}


def test_mutual_tls_with_passwords_needs_a_certificate_and_password_of_the_same_robot(
    tmp_path, certificates, users_file
):
    arguments = ["--users", str(users_file), *tls_arguments(certificates)[:6]]  # no --robots: --users names them
    with running_fleet(tmp_path, *arguments, scheme="tls") as fleet:
        with (
            zenoh_peer(fleet.endpoint, tls=robot_tls(certificates, "arm_1")) as no_password,
            zenoh_peer(fleet.endpoint, "arm_1", PASSWORDS["arm_1"], tls=robot_tls(certificates, "arm_2")) as mixed,
            zenoh_peer(fleet.endpoint, "arm_2", PASSWORDS["arm_2"], tls=robot_tls(certificates, "arm_2")) as arm_2,
        ):
            wait_linked(mixed)
            wait_linked(arm_2)
            arm_2.put("joshua/arm_2/status", status("arm_2"))
            fleet.wait_for("arm_2")
            no_password.put("joshua/arm_1/status", status("arm_1"))
            mixed.put("joshua/arm_1/status", status("arm_1"))
            mixed.put("joshua/arm_2/status", status("arm_2", nodes=[("forged", "running")]))
            time.sleep(READ_WAIT_S)  # time for the forged status to arrive, were it let through
            assert not linked_to_fleet(no_password)
        assert fleet.names() == {"arm_2"}
        assert [node["name"] for node in fleet.wait_for("arm_2")["nodes"]] == ["leader"]


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--listen", "tcp/0.0.0.0:7447"], "give --users FILE or --tls-ca FILE"),
        (["--listen", "tcp/10.1.2.3:7447", "--tls-ca", "ca.pem"], "--tls-ca needs --listen tls/HOST:PORT"),
        (["--listen", "tls/127.0.0.1:7447"], "tls/127.0.0.1:7447 needs --tls-certificate and --tls-private-key"),
        (["--listen", "tcp/127.0.0.1:7447", "--robots", "r.txt"], "--robots names the robots of --tls-ca"),
        (["--listen", "tcp/127.0.0.1:7447", "--users", "missing.txt"], "cannot read --users missing.txt"),
        (["--listen", "tcp/127.0.0.1:7447", "--offline-after", "0"], "--offline-after must be a number above 0"),
        (
            ["--listen", "tcp/127.0.0.1:7447", "--offline-after", "60", "--forget-after", "30"],
            "--forget-after (30 s) must be longer than --offline-after (60 s)",
        ),
    ],
)
def test_unusable_settings_stop_the_fleet_with_one_line(tmp_path, monkeypatch, arguments, message):
    monkeypatch.chdir(tmp_path)
    result = run_fleet(*arguments)
    assert result.returncode == 2, result.stderr
    assert message in result.stderr
    assert "Traceback" not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr


def test_a_bad_users_line_is_named_without_its_password(tmp_path):
    users = tmp_path / "users.txt"
    users.write_text("arm_1:first-SECRET-pw\nArm Two:second-SECRET-pw\n")
    result = run_fleet("--listen", "tcp/127.0.0.1:7447", "--users", str(users))
    assert result.returncode == 2
    assert f'{users}:2: "Arm Two" is not a robot name' in result.stderr
    assert "SECRET" not in result.stderr
    assert "Traceback" not in result.stderr
