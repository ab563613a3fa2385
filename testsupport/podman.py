"""Podman confined to one directory, for tests and benchmarks: its storage, its configuration, no host network.

Every container's storage (`graphroot`, temporary files through TMPDIR) lives under the directory
given, through the configuration files podman reads from CONTAINERS_CONF and CONTAINERS_STORAGE_CONF,
so that `make image` run with `Podman.environment()` lands there too. The directory of a build's cache
mounts (`RUN --mount=type=cache`: the wheels pip downloads), which podman keeps under TMPDIR, may instead be a
link to a directory shared by every storage of the machine (`build_cache`), so that a wheel is
downloaded once per machine rather than once per storage; a build holds its cache mount alone while it
runs (`sharing=locked`, with buildah's lock file inside the shared directory). Its run state (`runroot`) lives
in a short directory of its own under /run, removed by close(): podman hands the runroot to the
cleanup command a container's exit runs, which refuses one longer than 50 characters (a test's
directory is longer), and then every `podman run` waits 20 s for an exit that is never recorded. The
configuration fits a machine with hybrid cgroups v1/v2 and no service manager: runc (crun refuses
such hosts), the cgroupfs manager, events in a file, and open-file and process limits no higher than
this process has (podman's own defaults may exceed them, and runc cannot raise a hard limit).
Containers run with `--network none` or in a network namespace the caller made (NetworkNamespace);
builds use the host's network, which creates no bridge and no firewall rule.
"""

import os
import resource
import shutil
import subprocess
import tempfile
import uuid
from pathlib import Path

PODMAN_TIMEOUT_S = 120.0  # one podman command other than a build
BUILD_TIMEOUT_S = 1200.0  # an image build: pip installs the ROS 2 wheels from PyPI, g++ compiles the C++ nodes
PID_MAX = Path("/proc/sys/kernel/pid_max")
RUN_STATE_PARENT = "/run"  # a runroot here is short enough for podman's 50-character limit
# Where under TMPDIR podman keeps the cache mounts of builds: podman 4.3's buildah names the directory
# `buildah-cache`, later ones add the user's uid.
BUILD_CACHE_NAMES = ("buildah-cache", f"buildah-cache-{os.getuid()}")


def engine_missing() -> str | None:
    """Why podman cannot be used here (None when it can)."""
    for tool in ("podman", "runc"):
        if shutil.which(tool) is None:
            return f"{tool} is not installed (make setup installs it)"
    return None


def _limits() -> list[str]:
    """Open-file and process limits a container may have: this process's own (podman caps processes at pid_max)."""
    _, files = resource.getrlimit(resource.RLIMIT_NOFILE)
    _, processes = resource.getrlimit(resource.RLIMIT_NPROC)
    pid_max = int(PID_MAX.read_text())
    processes = pid_max if processes == resource.RLIM_INFINITY else min(processes, pid_max)
    return [f"nofile={files}:{files}", f"nproc={processes}:{processes}"]


class Podman:
    """podman with its storage and configuration under `directory`, its builds' cache mounts in `build_cache` when
    given (else under `directory` too); close() removes its run state."""

    def __init__(self, directory: Path, build_cache: Path | None = None):
        self.directory = directory
        self.runroot = Path(tempfile.mkdtemp(prefix="joshua-podman-", dir=RUN_STATE_PARENT))
        self.tmp = directory / "tmp"
        self.tmp.mkdir(parents=True, exist_ok=True)
        if build_cache is not None:
            build_cache.mkdir(parents=True, exist_ok=True)
            for name in BUILD_CACHE_NAMES:
                (self.tmp / name).symlink_to(build_cache, target_is_directory=True)
        limits = ", ".join(f'"{limit}"' for limit in _limits())
        self.containers_conf = directory / "containers.conf"
        self.containers_conf.write_text(
            f"[containers]\ndefault_ulimits = [{limits}]\n\n"
            '[engine]\ncgroup_manager = "cgroupfs"\nevents_logger = "file"\nruntime = "runc"\n'
        )
        self.storage_conf = directory / "storage.conf"
        self.storage_conf.write_text(
            f'[storage]\ndriver = "overlay"\ngraphroot = "{directory / "root"}"\nrunroot = "{self.runroot}"\n'
        )

    def __enter__(self) -> "Podman":
        return self

    def __exit__(self, *_exc) -> None:
        self.close()

    def close(self) -> None:
        """Remove the run state (the storage stays in `directory`, with the caller's other files)."""
        shutil.rmtree(self.runroot, ignore_errors=True)

    def environment(self, base: dict | None = None) -> dict:
        """An environment in which `podman` (and `make image`) use this storage and configuration."""
        return {
            **(base if base is not None else os.environ),
            "CONTAINERS_CONF": str(self.containers_conf),
            "CONTAINERS_STORAGE_CONF": str(self.storage_conf),
            "TMPDIR": str(self.tmp),
        }

    def command(self, *args) -> list[str]:
        return ["podman", *map(str, args)]

    def run(
        self, *args, timeout: float = PODMAN_TIMEOUT_S, check: bool = True, **kwargs
    ) -> subprocess.CompletedProcess:
        """Run one podman command; its output as text."""
        kwargs.setdefault("stdin", subprocess.DEVNULL)
        kwargs.setdefault("text", True)
        done = subprocess.run(
            self.command(*args), env=self.environment(), capture_output=True, timeout=timeout, **kwargs
        )
        if check and done.returncode != 0:
            raise RuntimeError(f"podman {' '.join(map(str, args))} exited {done.returncode}: {done.stderr.strip()}")
        return done

    def popen(self, *args, **kwargs) -> subprocess.Popen:
        return subprocess.Popen(self.command(*args), env=self.environment(), **kwargs)

    def image_exists(self, image: str) -> bool:
        return self.run("image", "exists", image, check=False).returncode == 0

    def image_size(self, image: str) -> int:
        """The image's size in bytes, as `podman images` counts it."""
        return int(self.run("image", "inspect", "--format", "{{.Size}}", image).stdout)

    def label(self, image: str, name: str) -> str:
        return self.run("image", "inspect", "--format", f'{{{{index .Labels "{name}"}}}}', image).stdout.strip()

    def remove_container(self, name: str) -> None:
        self.run("rm", "--force", "--time", "0", name, check=False)


def unique_name(prefix: str) -> str:
    """A container or namespace name no other test run on this machine uses."""
    return f"{prefix}-{uuid.uuid4().hex[:10]}"


class NetworkNamespace:
    """A network namespace holding only its loopback, up: containers joined to it reach each other, nothing else."""

    def __init__(self, name: str):
        self.name = name
        self.path = Path("/run/netns") / name

    def __enter__(self) -> "NetworkNamespace":
        subprocess.run(["ip", "netns", "add", self.name], check=True, capture_output=True)
        subprocess.run(["ip", "-n", self.name, "link", "set", "lo", "up"], check=True, capture_output=True)
        return self

    def __exit__(self, *_exc) -> None:
        subprocess.run(["ip", "netns", "delete", self.name], check=False, capture_output=True)

    @property
    def network_option(self) -> str:
        return f"--network=ns:{self.path}"

    def run(self, *args, **kwargs) -> subprocess.CompletedProcess:
        """A host command inside the namespace."""
        return subprocess.run(["ip", "netns", "exec", self.name, *map(str, args)], **kwargs)
