"""The robot's side of the fleet's credentials: what the dashboard hands zenoh, and one clear line when a
file named in the description cannot be used. No network."""

import subprocess
import sys
from pathlib import Path

import pytest

from joshua_runtime.dashboard.zenoh_link import robot_settings
from joshua_runtime.errors import SettingsError

ROOT = Path(__file__).resolve().parents[3]
MOCK_ARM = ROOT / "generated" / "mock_arm" / "manifest.json"
NONE = {"zenoh_password_file": "", "zenoh_tls_ca": "", "zenoh_tls_certificate": "", "zenoh_tls_private_key": ""}


def test_the_password_is_read_from_its_file_and_the_user_is_the_robots_name(tmp_path):
    password_file = tmp_path / "fleet-password"
    password_file.write_text("s3cret:with colon\n")
    settings = robot_settings("arm_1", "tcp/10.0.0.5:7447", NONE | {"zenoh_password_file": str(password_file)})
    assert settings == {"transport/auth/usrpwd/user": "arm_1", "transport/auth/usrpwd/password": "s3cret:with colon"}


def test_mutual_tls_hands_zenoh_the_paths(tmp_path):
    for name in ("ca.pem", "arm.pem", "arm.key"):
        (tmp_path / name).write_text("PEM")
    credentials = {
        "zenoh_password_file": "",
        "zenoh_tls_ca": str(tmp_path / "ca.pem"),
        "zenoh_tls_certificate": str(tmp_path / "arm.pem"),
        "zenoh_tls_private_key": str(tmp_path / "arm.key"),
    }
    assert robot_settings("arm", "tls/10.0.0.5:7447", credentials) == {
        "transport/link/tls/root_ca_certificate": str(tmp_path / "ca.pem"),
        "transport/link/tls/connect_certificate": str(tmp_path / "arm.pem"),
        "transport/link/tls/connect_private_key": str(tmp_path / "arm.key"),
        "transport/link/tls/enable_mtls": True,
    }


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (None, "cannot read zenoh_password_file {path}: No such file or directory"),
        ("", "zenoh_password_file {path} must hold one line, the password, without surrounding spaces"),
        ("two\nlines\n", "zenoh_password_file {path} must hold one line"),
        (" padded\n", "zenoh_password_file {path} must hold one line"),
        (b"\xff\xfe", "zenoh_password_file {path} is not UTF-8 text"),
    ],
)
def test_an_unusable_password_file_is_one_clear_error(tmp_path, content, message):
    path = tmp_path / "fleet-password"
    if isinstance(content, bytes):
        path.write_bytes(content)
    elif content is not None:
        path.write_text(content)
    with pytest.raises(SettingsError) as error:
        robot_settings("arm", "tcp/10.0.0.5:7447", NONE | {"zenoh_password_file": str(path)})
    assert str(error.value).startswith(message.format(path=path))


@pytest.mark.process
def test_the_dashboard_stops_with_one_line_when_a_credential_file_is_missing(tmp_path):
    missing = tmp_path / "absent.pem"
    result = subprocess.run(
        [sys.executable, "-m", "joshua_runtime.dashboard", "--manifest", str(MOCK_ARM), "--port", "0"]
        + ["--zenoh-connect", "tls/127.0.0.1:7447", "--zenoh-tls-ca", str(missing)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2, result.stderr
    assert result.stderr.strip() == f"dashboard: error: cannot read zenoh_tls_ca {missing}: No such file or directory"
