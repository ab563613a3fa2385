"""The Python interpreters on this machine that the compiler supports, and fresh environments of joshuac on them."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

from testsupport.joshuac_cli import ROOT

# The versions `requires-python` of joshuac and joshua-core admits.
SUPPORTED = ((3, 10), (3, 11), (3, 12), (3, 13))
# Creating an environment and installing joshuac into it: a wheel build of each of the two projects.
INSTALL_TIMEOUT_S = 300
_VERSION_QUERY = "import sys; print('%d.%d' % sys.version_info[:2])"


def _candidates() -> list[Path]:
    """Interpreters on PATH under their versioned names, then those of pyenv (PYENV_ROOT, else ~/.pyenv)."""
    found = []
    for major, minor in SUPPORTED:
        path = shutil.which(f"python{major}.{minor}")
        if path:
            found.append(Path(path))
    pyenv = Path(os.environ.get("PYENV_ROOT", Path.home() / ".pyenv")) / "versions"
    if pyenv.is_dir():
        found += sorted(pyenv.glob("*/bin/python3"))
    return found


def _version(interpreter: Path) -> tuple[int, int] | None:
    try:
        result = subprocess.run(
            [str(interpreter), "-c", _VERSION_QUERY], capture_output=True, text=True, timeout=30, check=True
        )
    except (OSError, subprocess.SubprocessError):
        return None  # a pyenv shim of a version that is not installed, for one
    major, minor = result.stdout.strip().split(".")
    return int(major), int(minor)


def supported_interpreters() -> dict[str, Path]:
    """`3.10` -> the first interpreter of that version found, for every supported version present."""
    found: dict[str, Path] = {}
    for interpreter in _candidates():
        version = _version(interpreter)
        if version in SUPPORTED and f"{version[0]}.{version[1]}" not in found:
            found[f"{version[0]}.{version[1]}"] = interpreter
    return dict(sorted(found.items()))


def _uv() -> str:
    local = ROOT / ".venv" / "bin" / "uv"
    return str(local) if local.exists() else "uv"


def install_joshuac(interpreter: Path, venv: Path) -> Path:
    """A fresh virtual environment on `interpreter` holding joshuac and joshua-core from this checkout.

    Offline from uv's cache when it holds every dependency, else from the package index. Returns its bin/."""
    env = {**os.environ, "UV_PYTHON_DOWNLOADS": "never"}
    env.pop("VIRTUAL_ENV", None)
    subprocess.run([_uv(), "venv", "-q", "-p", str(interpreter), str(venv)], env=env, check=True, timeout=60)
    # The projects are rebuilt every time: uv keys its cache of a local project on pyproject.toml alone.
    install = [_uv(), "pip", "install", "-q", "--python", str(venv / "bin" / "python")]
    install += ["--reinstall-package", "joshuac", "--reinstall-package", "joshua-core"]
    install += ["--refresh-package", "joshuac", "--refresh-package", "joshua-core", "./core", "."]
    offline = subprocess.run([*install, "--offline"], cwd=ROOT, env=env, capture_output=True, timeout=INSTALL_TIMEOUT_S)
    if offline.returncode != 0:
        subprocess.run(install, cwd=ROOT, env=env, check=True, timeout=INSTALL_TIMEOUT_S)
    return venv / "bin"
