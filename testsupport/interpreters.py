"""The Python interpreters on this machine that the compiler and the runtime support, and fresh environments
of joshuac, or of the runtime with its locked dependencies, on them."""

from __future__ import annotations

import functools
import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

from packaging.specifiers import SpecifierSet

from testsupport.joshuac_cli import ROOT

_HIGHEST_MINOR = 20  # 3.0 to 3.20 are looked at when reading a requires-python
# Creating an environment and installing joshuac into it: a wheel build of each of the two projects.
INSTALL_TIMEOUT_S = 300
_VERSION_QUERY = "import sys; print('%d.%d' % sys.version_info[:2])"


def admitted_versions(pyproject: Path) -> tuple[tuple[int, int], ...]:
    """The Python 3 versions the `requires-python` of a pyproject.toml admits."""
    specifiers = SpecifierSet(tomllib.loads(pyproject.read_text())["project"]["requires-python"])
    return tuple((3, minor) for minor in range(_HIGHEST_MINOR + 1) if specifiers.contains(f"3.{minor}"))


SUPPORTED = admitted_versions(ROOT / "pyproject.toml")  # joshuac's, which joshua-core shares
RUNTIME_SUPPORTED = admitted_versions(ROOT / "runtime" / "pyproject.toml")
DEVELOPMENT = f"{sys.version_info.major}.{sys.version_info.minor}"  # the development environment's, running the tests


def _candidates() -> list[Path]:
    """Interpreters on PATH under their versioned names, then those of pyenv (PYENV_ROOT, else ~/.pyenv).

    pyenv's shims on PATH are passed over: each takes 0.2 s to answer, and only reaches an interpreter
    of pyenv's versions, which are listed here themselves."""
    pyenv = Path(os.environ.get("PYENV_ROOT", Path.home() / ".pyenv"))
    search_path = os.pathsep.join(
        entry for entry in os.environ.get("PATH", "").split(os.pathsep) if Path(entry) != pyenv / "shims"
    )
    found = []
    for major, minor in sorted(set(SUPPORTED) | set(RUNTIME_SUPPORTED)):
        path = shutil.which(f"python{major}.{minor}", path=search_path)
        if path:
            found.append(Path(path))
    if (pyenv / "versions").is_dir():
        found += sorted((pyenv / "versions").glob("*/bin/python3"))
    return found


@functools.cache  # each test module that asks would run them all again
def _version(interpreter: Path) -> tuple[int, int] | None:
    try:
        result = subprocess.run(
            [str(interpreter), "-c", _VERSION_QUERY], capture_output=True, text=True, timeout=30, check=True
        )
    except (OSError, subprocess.SubprocessError):
        return None  # a pyenv shim of a version that is not installed, for one
    major, minor = result.stdout.strip().split(".")
    return int(major), int(minor)


def supported_interpreters(versions=SUPPORTED) -> dict[str, Path]:
    """`3.10` -> the first interpreter of that version found, for every version of `versions` present
    (default: joshuac's)."""
    found: dict[str, Path] = {}
    for interpreter in _candidates():
        version = _version(interpreter)
        if version in versions and f"{version[0]}.{version[1]}" not in found:
            found[f"{version[0]}.{version[1]}"] = interpreter
    return dict(sorted(found.items()))


def with_shared_bytecode(env: dict, directory: Path) -> dict:
    """`env` for processes of an environment without bytecode (a fresh one: uv installs none): where none
    may be written (PYTHONDONTWRITEBYTECODE) each would compile all it imports; instead they write it once
    in `directory` (never into the checkout) and share it."""
    shared = {key: value for key, value in env.items() if key != "PYTHONDONTWRITEBYTECODE"}
    shared["PYTHONPYCACHEPREFIX"] = str(directory)
    return shared


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


def install_runtime(interpreter: Path, venv: Path, extras: tuple[str, ...], groups: tuple[str, ...]) -> Path:
    """A fresh virtual environment on `interpreter` holding joshua-core, joshua-runtime (with `extras`) and
    joshuac from this checkout, their dependencies and the dependency `groups` at the versions of uv.lock,
    checked against its hashes, as the lock gives them for that Python. Returns its bin/."""
    env = {**os.environ, "UV_PYTHON_DOWNLOADS": "never"}
    env.pop("VIRTUAL_ENV", None)
    subprocess.run([_uv(), "venv", "-q", "-p", str(interpreter), str(venv)], env=env, check=True, timeout=60)
    export = [_uv(), "export", "--frozen", "--all-packages", "--no-emit-workspace", "--no-default-groups"]
    export += [word for extra in extras for word in ("--extra", extra)]
    export += [word for group in groups for word in ("--group", group)]
    export += ["--format", "requirements.txt", "--output-file", str(venv / "locked-requirements.txt")]
    subprocess.run([*export, "--quiet"], cwd=ROOT, env=env, check=True, timeout=60)
    python = str(venv / "bin" / "python")
    locked = [_uv(), "pip", "install", "-q", "--python", python, "--require-hashes"]
    locked += ["-r", str(venv / "locked-requirements.txt")]
    if subprocess.run([*locked, "--offline"], env=env, capture_output=True, timeout=INSTALL_TIMEOUT_S).returncode:
        subprocess.run(locked, env=env, check=True, timeout=INSTALL_TIMEOUT_S)
    # The projects are rebuilt every time: uv keys its cache of a local project on pyproject.toml alone.
    projects = [_uv(), "pip", "install", "-q", "--python", python, "--no-deps", "--reinstall"]
    projects += ["--refresh-package", "joshuac", "--refresh-package", "joshua-core", "--refresh-package"]
    projects += ["joshua-runtime", "./core", "./runtime", "."]
    if subprocess.run(
        [*projects, "--offline"], cwd=ROOT, env=env, capture_output=True, timeout=INSTALL_TIMEOUT_S
    ).returncode:
        subprocess.run(projects, cwd=ROOT, env=env, check=True, timeout=INSTALL_TIMEOUT_S)
    return venv / "bin"
