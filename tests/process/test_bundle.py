"""`joshuac build --bundle`: a fresh virtual environment made only from the bundle runs the robot.

The build goes to a directory outside the repository; install.sh makes a new environment from the
robot's own interpreter (not this test's environment) and installs the bundle's wheels and pinned
requirements into it, reaching PyPI as a robot does: uv asks the index which versions exist (it
cannot resolve offline on a machine whose cache holds only the wheels `make setup` fetched from
uv.lock's URLs) and takes the wheels themselves from its cache, so rclpy and OpenCV are not
downloaded again at every run.
The supervisor then runs from that environment, outside the repository, with a minimal environment.
"""

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from uv import find_uv_bin

ROOT = Path(__file__).resolve().parents[2]
JOSHUAC = Path(sys.executable).parent / "joshuac"
BASE_PYTHON = sys._base_executable  # the machine's python3.11, without this project's packages
INSTALL_TIMEOUT_S = 300
RUN_S = 8
RUNTIME_WHEEL = "wheels/joshua_runtime-0.1.0-py3-none-any.whl"
STAMP = ".joshuac-stamp"
# How this machine reaches PyPI (certificates, proxies, index) and where uv keeps its cache.
PYPI_ACCESS_VARIABLES = {
    "SSL_CERT_FILE",
    "SSL_CERT_DIR",
    "HTTP_PROXY",
    "HTTPS_PROXY",
    "NO_PROXY",
    "http_proxy",
    "https_proxy",
    "no_proxy",
    "UV_INDEX_URL",
    "UV_DEFAULT_INDEX",
    "UV_NATIVE_TLS",
    "UV_CACHE_DIR",
}


@pytest.fixture(scope="module")
def bundle(tmp_path_factory) -> Path:
    """The mock arm built with its bundle, outside the repository."""
    out = tmp_path_factory.mktemp("robot") / "mock_arm"
    built = subprocess.run(
        [str(JOSHUAC), "build", str(ROOT / "config" / "robots" / "mock_arm.pbtxt"), "-o", str(out), "--bundle"],
        capture_output=True,
        text=True,
        timeout=INSTALL_TIMEOUT_S,
    )
    assert built.returncode == 0, built.stderr
    return out


def clean_environment(tmp_path: Path, ros_env: dict, **extra) -> dict:
    """Only what a robot's shell would have: no PYTHONPATH, no virtual environment, no repository;
    its way to PyPI (certificates, proxies) as this machine's."""
    tools = tmp_path / "tools"
    tools.mkdir(exist_ok=True)
    if not (tools / "uv").exists():
        (tools / "uv").symlink_to(find_uv_bin())
    pypi_access = {name: value for name, value in os.environ.items() if name in PYPI_ACCESS_VARIABLES}
    return {
        **pypi_access,
        "PATH": f"{tools}:/usr/bin:/bin",
        "HOME": os.environ["HOME"],
        "ROS_DOMAIN_ID": ros_env["ROS_DOMAIN_ID"],
        "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST",
        **extra,
    }


def test_a_fresh_environment_made_only_from_the_bundle_runs_the_robot(bundle, tmp_path, ros_env):
    out = bundle
    assert sorted(path.name for path in (out / "wheels").iterdir()) == [
        "joshua_core-0.1.0-py3-none-any.whl",
        "joshua_runtime-0.1.0-py3-none-any.whl",
        "local-requirements.txt",
        "requirements.txt",
    ]
    assert (out / "install.sh").stat().st_mode & 0o111
    assert subprocess.run(["sha256sum", "--quiet", "-c", ".joshuac-stamp"], cwd=out).returncode == 0  # stamp covers it

    venv = tmp_path / "venv"
    env = clean_environment(tmp_path, ros_env, PYTHON=BASE_PYTHON)
    installed = subprocess.run(
        ["sh", str(out / "install.sh"), str(venv)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=INSTALL_TIMEOUT_S,
    )
    assert installed.returncode == 0, installed.stderr
    assert f"joshua_runtime installed in {venv}" in installed.stdout
    located = subprocess.run(
        [str(venv / "bin" / "python"), "-c", "import joshua_runtime; print(joshua_runtime.__file__)"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
    )
    assert located.stdout.startswith(str(venv)), located  # the bundle's copy, not this checkout

    run = subprocess.run(
        [str(venv / "bin" / "python"), str(out / "supervisor.py"), "--duration", str(RUN_S)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=RUN_S + 30,
    )
    assert run.returncode == 0, run.stderr
    assert "supervisor: ready: 4 of 4 nodes ready" in run.stderr
    for node in ("leader", "follower", "camera", "lidar"):
        assert f"{node}: pid" in run.stderr and f"{node}: final state: stopped (exited with code 0)" in run.stderr


def test_preflight_names_the_bundle_install_command_for_an_interpreter_without_the_runtime(bundle, tmp_path, ros_env):
    out = bundle
    run = subprocess.run(
        [BASE_PYTHON, str(out / "supervisor.py"), "--duration", "1"],
        cwd=tmp_path,
        env=clean_environment(tmp_path, ros_env),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode == 3
    assert (
        f"{BASE_PYTHON} cannot import the runtime (ModuleNotFoundError: No module named 'joshua_runtime'); "
        f"install it: sh {out / 'install.sh'}"
    ) in run.stderr
    assert "started pid" not in run.stderr


def patched_bundle(bundle: Path, tmp_path: Path, marker: Path) -> Path:
    """A copy of the bundle whose runtime wheel writes `marker` when joshua_runtime is imported."""
    copy = tmp_path / "bundle"
    shutil.copytree(bundle, copy, symlinks=True)
    wheel = copy / RUNTIME_WHEEL
    with zipfile.ZipFile(wheel) as source:
        members = [(info, source.read(info)) for info in source.infolist()]
    payload = f"\nimport pathlib\npathlib.Path({str(marker)!r}).write_text('patched')\n".encode()
    with zipfile.ZipFile(wheel, "w", zipfile.ZIP_DEFLATED) as target:
        for info, data in members:
            target.writestr(info, data + payload if info.filename == "joshua_runtime/__init__.py" else data)
    return copy


def install(out: Path, venv: Path, tmp_path: Path, ros_env: dict, **extra) -> subprocess.CompletedProcess:
    env = clean_environment(tmp_path, ros_env, PYTHON=BASE_PYTHON, **extra)
    return subprocess.run(
        ["sh", str(out / "install.sh"), str(venv)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=INSTALL_TIMEOUT_S,
    )


def test_a_wheel_changed_after_the_build_is_refused_before_anything_is_installed(bundle, tmp_path, ros_env):
    marker = tmp_path / "patch-ran"
    out = patched_bundle(bundle, tmp_path, marker)
    assert subprocess.run(["sha256sum", "--quiet", "-c", STAMP], cwd=out, capture_output=True).returncode != 0
    venv = tmp_path / "venv"
    installed = install(out, venv, tmp_path, ros_env)
    assert installed.returncode == 1, installed.stdout + installed.stderr
    assert installed.stderr == (
        f"install.sh: {RUNTIME_WHEEL} differs from the build ({out / STAMP}); nothing installed\n"
    )
    assert not venv.exists() and not marker.exists()


def test_a_file_the_build_did_not_write_in_wheels_is_refused(bundle, tmp_path, ros_env):
    out = tmp_path / "bundle"
    shutil.copytree(bundle, out, symlinks=True)
    shutil.copy(out / RUNTIME_WHEEL, out / "wheels" / "helper-1.0-py3-none-any.whl")
    venv = tmp_path / "venv"
    installed = install(out, venv, tmp_path, ros_env)
    assert installed.returncode == 1, installed.stdout + installed.stderr
    assert installed.stderr == (
        f"install.sh: wheels/helper-1.0-py3-none-any.whl is not part of the build ({out / STAMP}); nothing installed\n"
    )
    assert not venv.exists()


@pytest.mark.parametrize("installer", ["uv", "pip"])
def test_the_local_wheels_are_hash_pinned_too(bundle, tmp_path, ros_env, installer):
    """A wheel swapped behind a stamp that was made to match it still fails the installer's own hash check."""
    marker = tmp_path / "patch-ran"
    out = patched_bundle(bundle, tmp_path, marker)
    digest = subprocess.run(["sha256sum", RUNTIME_WHEEL], cwd=out, capture_output=True, text=True, check=True)
    stamp = out / STAMP
    lines = [digest.stdout if line.endswith(f"  {RUNTIME_WHEEL}\n") else line for line in stamp.open()]
    stamp.write_text("".join(lines))
    assert subprocess.run(["sha256sum", "--quiet", "-c", STAMP], cwd=out).returncode == 0
    venv = tmp_path / "venv"
    installed = install(out, venv, tmp_path, ros_env, JOSHUA_INSTALLER=installer)
    assert installed.returncode != 0, installed.stdout + installed.stderr
    assert RUNTIME_WHEEL.removeprefix("wheels/") in installed.stderr
    assert not marker.exists()
    imported = subprocess.run([str(venv / "bin" / "python"), "-c", "import joshua_runtime"], capture_output=True)
    assert imported.returncode != 0
