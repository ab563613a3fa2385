"""Container images: the mock arm's image size, its build and start times, with a cold and a cached base.

    .venv/bin/python bench/image.py [--quick] [--config config/robots/mock_arm.pbtxt]

Podman runs confined to one directory (testsupport/podman.py): runc, cgroupfs, no host network for
containers. The base is Debian 12 from debootstrap (testsupport/container_base.py); the image is
built by `make image` exactly as a user builds it, pip installing the pinned requirements from PyPI.

- base, cold: debootstrap into a fresh cache, then the import into an empty storage; cached: the
  machine's cached tarball imported into an empty storage (what a test session pays).
- build, cold: `make image` into that empty storage (every layer built, every wheel downloaded);
  cached: `make image` again with a changed description, so only the layers after the
  requirements' are rebuilt (the loop of a developer who edits the description).
- start: from `podman run` to the supervisor's "ready: N of N nodes ready", and the bare start of a
  container of the base (`podman run --rm BASE true`): the floor every container pays.
- size: the image, the base under it, and what the robot adds (its environment and build).

--quick skips the cold base (debootstrap takes minutes) and builds once, in a fresh storage whose
wheels come from the machine's build cache (testsupport/container_base.build_cache(), the one the
tests' builds use): its build is cold but for the download of the wheels, and says so. Without --quick
the build's cache is in its own storage, so every wheel is downloaded.
"""

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from testsupport import container_base  # noqa: E402
from testsupport.podman import BUILD_TIMEOUT_S, Podman, unique_name  # noqa: E402

READY_TIMEOUT_S = 180.0
POLL_S = 0.1
STARTS = 3
QUICK_STARTS = 1
MB = 1e6
CHANGED_DESCRIPTION = "leader.rate_hz=49"  # a different build: every layer after the requirements' is rebuilt


def make_image(podman: Podman, base: str, config: str, context: Path, overrides: str = "") -> tuple[str, float]:
    """`make image` into `podman`'s storage: (tag, seconds)."""
    started = time.monotonic()
    command = ["make", "--no-print-directory", "-o", "setup", "image", f"CONFIG={config}", f"BASE={base}"]
    done = subprocess.run(
        [*command, f"CONTEXT={context}", f"SET={overrides}"],
        cwd=ROOT,
        env=podman.environment(),
        capture_output=True,
        text=True,
        timeout=BUILD_TIMEOUT_S,
    )
    if done.returncode != 0:
        sys.exit(f"bench/image.py: make image failed:\n{done.stdout[-3000:]}{done.stderr[-3000:]}")
    tag = next(line.split()[3] for line in done.stdout.splitlines() if line.startswith("make image: built "))
    return tag, time.monotonic() - started


def time_to_ready(podman: Podman, image: str) -> float:
    """Seconds from `podman run` to every node ready."""
    name = unique_name("bench-image")
    started = time.monotonic()
    podman.run("run", "--detach", "--name", name, "--network=none", image)
    try:
        while time.monotonic() - started < READY_TIMEOUT_S:
            output = podman.run("logs", name, check=False).stderr
            if "supervisor: ready:" in output:
                return time.monotonic() - started
            time.sleep(POLL_S)
        sys.exit(f"bench/image.py: {image} was not ready within {READY_TIMEOUT_S} s")
    finally:
        podman.remove_container(name)


def bare_start(podman: Podman, base: str) -> float:
    started = time.monotonic()
    podman.run("run", "--rm", "--network=none", base, "true")
    return time.monotonic() - started


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="no cold base, one build, one start")
    parser.add_argument("--config", default="config/robots/mock_arm.pbtxt")
    args = parser.parse_args()

    build_cache = container_base.build_cache() if args.quick else None
    with (
        tempfile.TemporaryDirectory(prefix="bench-image-") as work,
        Podman(Path(work) / "podman", build_cache=build_cache) as podman,
    ):
        work = Path(work)
        if not args.quick:
            started = time.monotonic()
            container_base.build_tarball(work / "rootfs.tar")
            print(f"base, cold: debootstrap {time.monotonic() - started:.1f} s")
        started = time.monotonic()
        base = container_base.import_base(podman)
        print(f"base, cached: import {time.monotonic() - started:.1f} s into an empty storage")

        tag, cold = make_image(podman, base, args.config, work / "context")
        wheels = "wheels from PyPI" if not args.quick else "--quick: wheels from the machine's build cache if there"
        print(f"build, cold (empty storage; {wheels}): {cold:.1f} s")
        if not args.quick:
            _, cached = make_image(podman, base, args.config, work / "context", CHANGED_DESCRIPTION)
            print(
                f"build, cached (the description changed, the requirements layer reused): {cached:.1f} s "
                f"({cold / cached:.1f}x faster)"
            )

        starts = [time_to_ready(podman, tag) for _ in range(QUICK_STARTS if args.quick else STARTS)]
        floor = min(bare_start(podman, base) for _ in range(QUICK_STARTS if args.quick else STARTS))
        print(
            f"start: podman run to every node ready {min(starts):.2f} s (best of {len(starts)}); "
            f"bare container start {floor:.2f} s; ratio {min(starts) / floor:.1f}"
        )

        size, base_size = podman.image_size(tag), podman.image_size(base)
        print(
            f"size: {tag} {size / MB:.1f} MB; base {base_size / MB:.1f} MB; the robot adds {(size - base_size) / MB:.1f} MB"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
