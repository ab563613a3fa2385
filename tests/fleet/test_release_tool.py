"""The robot's side of a rollout (OUT/ansible/files/release_tool.py and health_gate.py) run as the playbooks
run them, on a release root in a temporary directory: unpacking, verifying, switching, gating and going back."""

import hashlib
import io
import os
import signal
import subprocess
import sys
import tarfile
import time
from pathlib import Path

import pytest

from testsupport.joshuac_cli import joshuac

ROBOT = """robot_config {
  name: "r"
  mode: MODE_TELEOPERATION
  shutdown { sigint_grace_s: 1 sigterm_grace_s: 1 }
  node { name: "steady" type: CUSTOM executable: "/bin/sleep" args: ["600"] }
%s}
"""
CRASH = '  node { name: "crash" type: CUSTOM executable: "/bin/sh" args: ["-c", "echo no device; exit 1"] }\n'
GATE_TIMEOUT_S = "60"


@pytest.fixture(scope="module")
def releases(tmp_path_factory):
    """Two signed releases of robot `arm`: a good one and one whose node `crash` exits 1 at start."""
    directory = tmp_path_factory.mktemp("releases")
    assert joshuac("keygen", str(directory / "release.key")).returncode == 0
    (directory / "good.pbtxt").write_text(ROBOT % "")
    (directory / "crash.pbtxt").write_text(ROBOT % CRASH)
    fleet = 'fleet_config {{ name: "lab" robot {{ name: "arm" description: "{}" address: "10.0.0.1" set: "python_executable={}" }} }}\n'
    built = {}
    for name in ("good", "crash"):
        (directory / f"{name}-fleet.pbtxt").write_text(fleet.format(f"{name}.pbtxt", sys.executable))
        done = joshuac("build", f"{name}-fleet.pbtxt", "-o", name, "--sign", "release.key", cwd=directory)
        assert done.returncode == 0, done.stderr
        built[name] = directory / name
    return directory, built


def release_id(release: Path) -> str:
    return hashlib.sha256((release / ".joshuac-stamp").read_bytes()).hexdigest()[:12]


def tool(out: Path, name: str, *args, env=None) -> subprocess.CompletedProcess:
    script = out / "ansible/files" / name
    command = [sys.executable, str(script), *map(str, args)]
    return subprocess.run(command, capture_output=True, text=True, timeout=120, env=env)


def send(out: Path, root: Path) -> str:
    """What the playbook's copy step does: the release as one archive, unpacked under ROOT/releases."""
    release = out / "robots/arm"
    archive = root / "sent.tar"
    root.mkdir(exist_ok=True)
    subprocess.run(["tar", "--create", "--file", str(archive), "--directory", str(release), "."], check=True)
    assert (
        tool(out, "release_tool.py", "--root", root, "prepare", "--archive-bytes", archive.stat().st_size).returncode
        == 0
    )
    done = tool(out, "release_tool.py", "--root", root, "unpack", release_id(release), archive)
    assert done.returncode == 0, done.stdout
    return release_id(release)


def verify(out: Path, root: Path, release: str, key: Path) -> subprocess.CompletedProcess:
    return tool(out, "release_tool.py", "--root", root, "verify", release, "--key", key)


def test_a_changed_added_or_unsigned_file_is_refused_by_name_and_the_copy_removed(releases, tmp_path):
    directory, built = releases
    out, key = built["good"], directory / "release.key.pub"
    cases = {
        "supervisor.py differs from the release's .joshuac-stamp (signed)": lambda d: (d / "supervisor.py").write_text("x"),
        "wheels/extra.whl is not part of the release (not in its .joshuac-stamp)": lambda d: (d / "wheels/extra.whl").write_text("x"),
        "manifest.json is missing from the release": lambda d: (d / "manifest.json").unlink(),
        "the release is not signed (.joshuac-stamp.sig is missing)": lambda d: (d / ".joshuac-stamp.sig").unlink(),
    }  # fmt: skip
    for number, (refusal, change) in enumerate(cases.items()):
        root = tmp_path / f"root{number}"
        release = send(out, root)
        change(root / "releases" / f".incoming-{release}")
        done = verify(out, root, release, key)
        assert done.returncode == 1 and done.stdout.strip().startswith(refusal), done.stdout
        assert sorted(os.listdir(root / "releases")) == []
    root = tmp_path / "signed-by-another"
    release = send(out, root)
    assert joshuac("keygen", str(tmp_path / "other.key")).returncode == 0
    done = verify(out, root, release, tmp_path / "other.key.pub")
    assert done.returncode == 1 and done.stdout.startswith("the signature .joshuac-stamp.sig does not match")
    root = tmp_path / "good"
    release = send(out, root)
    done = verify(out, root, release, key)
    assert done.returncode == 0 and "signature and every file checked" in done.stdout
    assert sorted(os.listdir(root / "releases")) == [release]


def test_an_archive_reaching_outside_the_release_is_refused(releases, tmp_path):
    out = releases[1]["good"]
    for member in ("../escape", "/etc/owned"):
        archive = tmp_path / "bad.tar"
        with tarfile.open(archive, "w") as tar:
            info = tarfile.TarInfo(member)
            info.size = 1
            tar.addfile(info, io.BytesIO(b"x"))
        done = tool(out, "release_tool.py", "--root", tmp_path / "root", "unpack", "abcdefabcdef", archive)
        assert done.returncode == 1 and "which is not a file or directory inside it" in done.stdout
    archive = tmp_path / "link.tar"
    with tarfile.open(archive, "w") as tar:
        info = tarfile.TarInfo("supervisor.py")
        info.type, info.linkname = tarfile.SYMTYPE, "/etc/passwd"
        tar.addfile(info)
    done = tool(out, "release_tool.py", "--root", tmp_path / "root", "unpack", "abcdefabcdef", archive)
    assert done.returncode == 1 and "'supervisor.py'" in done.stdout
    assert not (tmp_path / "escape").exists()


def test_a_release_that_does_not_fit_is_refused_before_it_is_sent(releases, tmp_path):
    out = releases[1]["good"]
    done = tool(out, "release_tool.py", "--root", tmp_path, "prepare", "--archive-bytes", 2**50)
    assert done.returncode == 1
    assert done.stdout.startswith(f"{tmp_path}/releases has ") and "MiB free, the release needs" in done.stdout


def start_args(root: Path) -> list[str]:
    return ["--robot", "arm", "--start", "supervisor", "--python", sys.executable]


def gate(out: Path, root: Path, release: str = "") -> subprocess.CompletedProcess:
    return tool(
        out,
        "health_gate.py",
        "--root",
        root,
        *start_args(root),
        "--release",
        release,
        "--timeout",
        GATE_TIMEOUT_S,
    )


def test_switch_gate_and_going_back_keep_current_on_a_complete_release(releases, tmp_path):
    directory, built = releases
    key = directory / "release.key.pub"
    root = tmp_path / "opt-joshua"
    good, crash = built["good"], built["crash"]
    first = send(good, root)
    assert verify(good, root, first, key).returncode == 0
    switched = tool(good, "release_tool.py", "--root", root, "switch", first, *start_args(root))
    try:
        assert switched.stdout.strip() == f"switched from nothing to {first}"
        ready = gate(good, root, first)
        assert ready.returncode == 0 and ready.stdout.startswith(f"ready: 1 of 1 nodes ready (build {first})"), (
            ready.stdout
        )
        pid = (root / "run/supervisor.pid").read_text().strip()

        second = send(crash, root)
        assert verify(crash, root, second, key).returncode == 0
        tool(crash, "release_tool.py", "--root", root, "switch", second, *start_args(root))
        assert os.readlink(root / "current") == f"releases/{second}"
        assert os.readlink(root / "previous") == f"releases/{first}"
        failed = gate(crash, root, second)
        assert failed.returncode == 1
        assert "crash" in failed.stdout and ("failed" in failed.stdout or "exited" in failed.stdout), failed.stdout
        back = tool(crash, "release_tool.py", "--root", root, "recover", second, *start_args(root),
                    "--current-before", first, "--previous-before", "")  # fmt: skip
        assert back.stdout.strip() == f"rolled back from {second} to {first}", back.stdout
        assert os.readlink(root / "current") == f"releases/{first}" and not os.path.lexists(root / "previous")
        assert gate(good, root, first).returncode == 0
        assert (root / "run/supervisor.pid").read_text().strip() != pid  # started again

        assert tool(good, "release_tool.py", "--root", root, "prune").returncode == 0
        assert sorted(os.listdir(root / "releases")) == [first]
    finally:
        stop_supervisor(root)


def stop_supervisor(root: Path) -> None:
    pid_file = root / "run/supervisor.pid"
    if not pid_file.exists():
        return
    pid = int(pid_file.read_text())
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    deadline = time.monotonic() + 30
    while Path(f"/proc/{pid}").exists() and time.monotonic() < deadline:
        time.sleep(0.1)


def test_the_systemd_start_method_installs_the_releases_units_and_starts_its_target(releases, tmp_path):
    """The tool's part with systemd, which does not run where the tests run: a `systemctl` on PATH records what it
    is asked (the units themselves pass systemd-analyze verify in tests/process/test_systemd_units.py)."""
    directory, built = releases
    key = directory / "release.key.pub"
    calls = tmp_path / "systemctl.calls"
    fake = tmp_path / "bin" / "systemctl"
    fake.parent.mkdir()
    fake.write_text(f'#!/bin/sh\necho "$*" >> {calls}\n')
    fake.chmod(0o755)
    env = dict(os.environ, PATH=f"{fake.parent}:{os.environ['PATH']}")
    units = tmp_path / "etc-systemd-system"
    units.mkdir()
    (units / "joshua-arm-gone.service").write_text("a node of an older release")
    (units / "ssh.service").write_text("not the robot's")
    root = tmp_path / "opt-joshua"
    systemd = ["--robot", "arm", "--start", "systemd", "--unit-dir", units]
    first = send(built["good"], root)
    assert verify(built["good"], root, first, key).returncode == 0
    done = tool(built["good"], "release_tool.py", "--root", root, "switch", first, *systemd, env=env)
    assert done.returncode == 0, done.stdout
    assert calls.read_text().splitlines() == ["daemon-reload", "enable joshua-arm.target", "start joshua-arm.target"]
    release_units = sorted(os.listdir(root / "current" / "systemd"))
    assert sorted(os.listdir(units)) == sorted([*release_units, "ssh.service"])
    second = send(built["crash"], root)
    assert verify(built["crash"], root, second, key).returncode == 0
    calls.unlink()
    done = tool(built["crash"], "release_tool.py", "--root", root, "switch", second, *systemd, env=env)
    assert done.returncode == 0, done.stdout
    assert calls.read_text().splitlines()[0] == "stop joshua-arm.target"  # before current moves
    assert "joshua-arm-crash.service" in os.listdir(units)
