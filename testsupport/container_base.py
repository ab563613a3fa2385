"""A Debian 12 base image made with debootstrap, without any container registry, built once per machine.

    python -m testsupport.container_base          # builds the base tarball when it is not cached yet

The root file system is made by `debootstrap --variant=minbase` from Debian's archive with the
packages every stage of a generated Containerfile looks for (Python, venv, catatonit, Mesa's EGL,
libpython for the C++ nodes), so an image build installs no system package except the compiler of
the C++ nodes' build stage. The tarball is cached under $XDG_CACHE_HOME/joshua/ (~/.cache/joshua/),
named after what it holds, so that reruns of the tests and other checkouts on the machine reuse it;
a lock keeps two test runs from making it at the same time. Tests import it into their own storage.
Beside it, `build_cache()` holds the cache mounts of the images' builds (the wheels pip downloads), which every
test storage of the machine uses (testsupport/podman.py), so that the wheels come from PyPI once.
"""

import fcntl
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from joshua_codegen.emitters.containerfile import (
    BUILD_PACKAGES,
    CPP_RUN_PACKAGES,
    EXTRA_PACKAGES,
    RUN_PACKAGES,
)

SUITE = "bookworm"
MIRROR = "http://deb.debian.org/debian"
PACKAGES = sorted(
    {*BUILD_PACKAGES, *RUN_PACKAGES, *CPP_RUN_PACKAGES, *(p for ps in EXTRA_PACKAGES.values() for p in ps)}
)
DEBOOTSTRAP_TIMEOUT_S = 1200.0
# Downloaded packages and package lists: an image build runs apt-get update itself when it needs them.
DROPPED = ("var/cache/apt/archives", "var/lib/apt/lists")
REPOSITORY = "localhost/joshua-base/debian-bookworm"


def cache_root() -> Path:
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "joshua"


def build_cache() -> Path:
    """The cache mounts (`RUN --mount=type=cache`) the image builds of every test storage on the machine share."""
    return cache_root() / "build-cache"


def base_key() -> str:
    """Names the base after what makes it: suite, mirror and packages."""
    return hashlib.sha256(f"{SUITE} {MIRROR} {' '.join(PACKAGES)}".encode()).hexdigest()[:12]


def base_image() -> str:
    """The name the base is imported under."""
    return f"{REPOSITORY}:{base_key()}"


def tarball_path() -> Path:
    return cache_root() / f"debootstrap-{SUITE}" / f"rootfs-{base_key()}.tar"


def build_tarball(tarball: Path) -> None:
    """debootstrap the base and write its root file system to `tarball` (slow: minutes)."""
    with tempfile.TemporaryDirectory(prefix="rootfs-", dir=tarball.parent) as work:
        rootfs = Path(work) / "rootfs"
        subprocess.run(
            ["debootstrap", "--variant=minbase", f"--include={','.join(PACKAGES)}", SUITE, str(rootfs), MIRROR],
            check=True,
            capture_output=True,
            timeout=DEBOOTSTRAP_TIMEOUT_S,
        )
        for dropped in DROPPED:
            for entry in (rootfs / dropped).glob("*"):
                if entry.is_file():
                    entry.unlink()
        partial = Path(work) / "rootfs.tar"
        subprocess.run(["tar", "--numeric-owner", "-C", str(rootfs), "-cf", str(partial), "."], check=True)
        partial.rename(tarball)


def ensure_tarball() -> Path:
    """The base's root file system as a tarball, made now when the cache lacks it (about a minute)."""
    tarball = tarball_path()
    tarball.parent.mkdir(parents=True, exist_ok=True)
    with open(tarball.parent / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not tarball.is_file():
            if shutil.which("debootstrap") is None:
                raise RuntimeError("debootstrap is not installed (make setup installs it)")
            for stale in tarball.parent.glob("rootfs-*.tar"):
                stale.unlink()
            build_tarball(tarball)
    return tarball


def import_base(podman) -> str:
    """The base imported into `podman`'s storage (once); its image name."""
    image = base_image()
    if not podman.image_exists(image):
        with open(ensure_tarball(), "rb") as tarball:
            podman.run("import", "--quiet", "-", image, stdin=tarball, timeout=DEBOOTSTRAP_TIMEOUT_S)
    return image


if __name__ == "__main__":
    print(ensure_tarball())
    sys.exit(0)
