"""`build --image`: the bundle plus what a container image of the robot is built from, as output files.

OUT becomes a complete build context: the bundle (OUT/wheels/, OUT/install.sh), OUT/Containerfile,
OUT/.containerignore, and, when the robot needs them, the dashboard's page (OUT/web/, copied from
web/dist, which `make setup` builds) and the sources of the C++ nodes it runs (OUT/cpp/, compiled in
the image's build stage). Like the bundle, it is made from joshuac's source tree.
"""

from pathlib import Path

from joshua_codegen.bundle import SOURCE_ROOT, BundleError, bundle_files
from joshua_codegen.emitters.containerfile import (
    CONTAINERFILE,
    CONTAINERIGNORE,
    CPP_DIR,
    PAGE_DIR,
    ContainerfileError,
    containerfile,
    containerignore,
)
from joshua_codegen.model import Robot
from joshua_codegen.ownership import STAMP
from joshua_core.dashboard import PROCESS_TYPE as DASHBOARD_TYPE

PAGE_SOURCE = SOURCE_ROOT / "web" / "dist"
PAGE_SKIPPED = {".built"}  # set-up's own marker of the last page build
CPP_SOURCE = SOURCE_ROOT / "cpp"
CPP_SOURCE_SUFFIXES = {".cpp", ".hpp"}
CPP_MAKEFILE = "Makefile"


class ImageError(Exception):
    """The image's build context cannot be made here."""


def _tree(root: Path, keep) -> dict[str, bytes]:
    """{path relative to root: content} of the regular files under root that `keep(path)` accepts."""
    return {
        path.relative_to(root).as_posix(): path.read_bytes()
        for path in sorted(root.rglob("*"))
        if path.is_file() and not path.is_symlink() and keep(path)
    }


def page_files(robot: Robot) -> dict[str, bytes]:
    """The dashboard's built page under web/, when the robot has a dashboard."""
    if not any(process.node_type == DASHBOARD_TYPE for process in robot.processes):
        return {}
    if not (PAGE_SOURCE / "index.html").is_file():
        raise ImageError(f"the dashboard's page is not built ({PAGE_SOURCE / 'index.html'} is missing): run make setup")
    files = _tree(PAGE_SOURCE, lambda path: path.name not in PAGE_SKIPPED)
    return {f"{PAGE_DIR}/{name}": data for name, data in files.items()}


def cpp_binaries(robot: Robot) -> list[str]:
    """The C++ binaries the robot's nodes run (cpp/Makefile builds every binary of the registry)."""
    return sorted({process.cpp_binary for process in robot.processes if process.cpp_binary})


def cpp_files(binaries: list[str]) -> dict[str, bytes]:
    """The sources and Makefile of the C++ nodes under cpp/, when the robot runs any."""
    if not binaries:
        return {}
    files = _tree(CPP_SOURCE, lambda path: path.suffix in CPP_SOURCE_SUFFIXES or path.name == CPP_MAKEFILE)
    return {f"{CPP_DIR}/{name}": data for name, data in files.items()}


def image_files(robot: Robot, prefix: str, files: dict[str, str | bytes]) -> dict[str, str | bytes]:
    """`files` (the rendered build) with the bundle and the image's files added."""
    if robot.hosts:
        raise ImageError(
            "--image makes one container of the whole robot, and this robot runs on several computers (host blocks): "
            "build an image of a description without them"
        )
    try:
        binaries = cpp_binaries(robot)
        page = page_files(robot)
        written = containerfile(robot, prefix, binaries, page=bool(page))  # a prefix it refuses, before the wheels
        context = {**files, **bundle_files(robot), **page, **cpp_files(binaries), CONTAINERFILE: written}
    except (BundleError, ContainerfileError) as exc:
        raise ImageError(str(exc)) from exc
    context[CONTAINERIGNORE] = containerignore(robot, [*context, CONTAINERIGNORE, STAMP])
    return context
