"""Builds the ROS 2 interface packages of interfaces/ into the environment (C, typesupport, Python).

No wheel ships these packages, so set-up generates them with the rosidl generators the ROS wheels
bring (.msg/.srv/.action -> .idl -> C, C typesupport, Fast DDS typesupport, introspection, Python)
and compiles them with the system C/C++ compiler, installing libraries into <prefix>/lib (on the
library path the ROS wheels set), the Python package into site-packages, headers, definitions and
ament index entries under <prefix>/include and <prefix>/share. A stamp holding the hash of the
inputs makes a second run a no-op.

    python scripts/build_ros_interfaces.py [--force]
"""

from __future__ import annotations

import argparse
import concurrent.futures
import hashlib
import os
import pathlib
import shutil
import subprocess
import sys
import sysconfig
import tempfile

REPO = pathlib.Path(__file__).resolve().parent.parent
INTERFACES = REPO / "interfaces"
PREFIX = pathlib.Path(sys.prefix)
SITE_PACKAGES = pathlib.Path(sysconfig.get_paths()["purelib"])
KINDS = ("msg", "srv", "action")
# Interface packages each package's definitions refer to (services and actions pull in the last three).
DEPENDENCIES: dict[str, tuple[str, ...]] = {
    "tf2_msgs": (
        "builtin_interfaces",
        "std_msgs",
        "geometry_msgs",
        "service_msgs",
        "action_msgs",
        "unique_identifier_msgs",
    ),
}
STAMP_NAME = "joshua-build.stamp"
COMPILE_JOBS = 2


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--force", action="store_true", help="rebuild even when the stamp matches")
    args = parser.parse_args()
    os.environ.setdefault("AMENT_PREFIX_PATH", str(PREFIX))
    for package in sorted(DEPENDENCIES):
        stamp = PREFIX / "share" / package / STAMP_NAME
        digest = _input_digest(package)
        if not args.force and stamp.is_file() and stamp.read_text() == digest and _importable(package):
            continue
        print(f"build_ros_interfaces: building {package}", flush=True)
        try:
            _build(package)
        except (subprocess.CalledProcessError, OSError) as exc:
            print(f"build_ros_interfaces: {package}: {exc}", file=sys.stderr)
            return 1
        stamp.write_text(digest)
    return 0


def _input_digest(package: str) -> str:
    digest = hashlib.sha256(pathlib.Path(__file__).read_bytes())
    digest.update(sys.version.encode())
    for path in sorted((INTERFACES / package).rglob("*")):
        if path.is_file():
            digest.update(path.relative_to(INTERFACES).as_posix().encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()


def _importable(package: str) -> bool:
    return (SITE_PACKAGES / package / "__init__.py").is_file()


def _definitions(package: str) -> list[pathlib.Path]:
    root = INTERFACES / package
    return sorted(path.relative_to(root) for kind in KINDS for path in (root / kind).glob(f"*.{kind}"))


def _build(package: str) -> None:
    with tempfile.TemporaryDirectory(prefix=f"{package}-") as tmp:
        work = pathlib.Path(tmp)
        idl_files = _translate(package, work / "idl")
        gen = work / "gen"
        _generate(package, idl_files, gen)
        libs = work / "lib"
        libs.mkdir()
        _compile(package, gen, libs)
        _install(package, work, gen, libs)


def _translate(package: str, out: pathlib.Path) -> list[str]:
    """.msg/.srv/.action -> .idl; returns the `root:relative` paths the generators take."""
    from rosidl_adapter.action import convert_action_to_idl
    from rosidl_adapter.msg import convert_msg_to_idl
    from rosidl_adapter.srv import convert_srv_to_idl

    converters = {".msg": convert_msg_to_idl, ".srv": convert_srv_to_idl, ".action": convert_action_to_idl}
    root = INTERFACES / package
    idl_files = []
    for relative in _definitions(package):
        (out / relative.parent).mkdir(parents=True, exist_ok=True)
        _quietly(converters[relative.suffix], root, package, relative, out / relative.parent)
        idl_files.append(f"{out}:{relative.with_suffix('.idl').as_posix()}")
    return idl_files


def _generators():
    """(output name, generator) pairs; the classes are the rosidl CLI's extensions, called directly
    because the ROS wheels register each entry point twice, which the CLI's loader refuses."""
    from rosidl_generator_c.cli import GenerateC
    from rosidl_generator_py.cli import GeneratePython
    from rosidl_typesupport_c.cli import GenerateCTypesupport
    from rosidl_typesupport_fastrtps_c.cli import GenerateFastRTPSCTypesupport
    from rosidl_typesupport_introspection_c.cli import GenerateIntrospectionCTypesupport

    return (
        ("c", GenerateC("c")),
        ("typesupport_c", GenerateCTypesupport("c")),
        ("fastrtps_c", GenerateFastRTPSCTypesupport("fastrtps_c")),
        ("introspection_c", GenerateIntrospectionCTypesupport("introspection_c")),
        (
            "py",
            GeneratePython(
                "py",
                typesupport_implementations=[
                    "rosidl_typesupport_c",
                    "rosidl_typesupport_fastrtps_c",
                    "rosidl_typesupport_introspection_c",
                ],
            ),
        ),
    )


def _generate(package: str, idl_files: list[str], gen: pathlib.Path) -> None:
    include_paths = [str(PREFIX / "share" / dependency) for dependency in DEPENDENCIES[package]]
    for name, generator in _generators():
        _quietly(generator.generate, package, idl_files, include_paths, output_path=gen / name / package)


def _quietly(function, *args, **kwargs):
    """The generators print a line per file read and written, and warn that the wheels declare their
    entry points twice; keep set-up's output short (failures raise)."""
    with open(os.devnull, "w") as devnull:
        streams = sys.stdout, sys.stderr
        sys.stdout = sys.stderr = devnull
        try:
            return function(*args, **kwargs)
        finally:
            sys.stdout, sys.stderr = streams


def _compile(package: str, gen: pathlib.Path, libs: pathlib.Path) -> None:
    include_flags = [f"-I{gen / name}" for name in ("c", "typesupport_c", "fastrtps_c", "introspection_c")]
    include_flags += [f"-I{PREFIX / 'include'}"]
    include_flags += [f"-I{path}" for path in sorted((PREFIX / "include").iterdir()) if path.is_dir()]
    deps = DEPENDENCIES[package]
    lib_flags = [f"-L{PREFIX / 'lib'}", f"-L{libs}", "-Wl,-rpath,$ORIGIN"]

    def sources(name: str, *patterns: str) -> list[str]:
        return sorted(str(p) for pattern in patterns for p in (gen / name / package).rglob(pattern))

    def link(*suffixes: str) -> list[str]:
        return [f"-l{dependency}__{suffix}" for dependency in deps for suffix in suffixes]

    own = f"-l{package}__rosidl_generator_c"
    libraries = {
        "rosidl_generator_c": (sources("c", "*.c"), [*link("rosidl_generator_c"), "-lrosidl_runtime_c", "-lrcutils"]),
        "rosidl_typesupport_introspection_c": (
            sources("introspection_c", "*.c"),
            [
                own,
                *link("rosidl_typesupport_introspection_c", "rosidl_generator_c"),
                "-lrosidl_typesupport_introspection_c",
                "-lrosidl_runtime_c",
                "-lrcutils",
            ],
        ),
        "rosidl_typesupport_fastrtps_c": (
            sources("fastrtps_c", "*.cpp"),
            [
                own,
                *link("rosidl_typesupport_fastrtps_c", "rosidl_generator_c"),
                "-lrosidl_typesupport_fastrtps_c",
                "-lrosidl_typesupport_fastrtps_cpp",
                "-lfastcdr",
                "-lrmw",
                "-lrosidl_runtime_c",
                "-lrcutils",
            ],
        ),
        "rosidl_typesupport_c": (
            sources("typesupport_c", "*.cpp"),
            [
                own,
                *link("rosidl_typesupport_c", "rosidl_generator_c"),
                "-lrosidl_typesupport_c",
                "-lrosidl_runtime_c",
                "-lrcutils",
            ],
        ),
    }
    # The generator_c library comes first: every other library links against it.
    first, *rest = libraries.items()
    _shared_library(libs / f"lib{package}__{first[0]}.so", first[1][0], include_flags, lib_flags + first[1][1])
    with concurrent.futures.ThreadPoolExecutor(COMPILE_JOBS) as pool:
        jobs = [
            pool.submit(_shared_library, libs / f"lib{package}__{name}.so", srcs, include_flags, lib_flags + flags)
            for name, (srcs, flags) in rest
        ]
        for job in jobs:
            job.result()

    import numpy

    python_flags = [f"-I{sysconfig.get_paths()['include']}", f"-I{numpy.get_include()}"]
    py_dir = gen / "py" / package
    message_sources = sorted(str(p) for p in py_dir.rglob("_*_s.c") if ".ep." not in p.name)
    _shared_library(
        libs / f"lib{package}__rosidl_generator_py.so",
        message_sources,
        include_flags + python_flags,
        lib_flags
        + [
            own,
            f"-l{package}__rosidl_typesupport_c",
            *link("rosidl_generator_py", "rosidl_generator_c"),
            "-lrosidl_runtime_c",
            "-lrcutils",
        ],
    )
    extension_flags = [f"-L{PREFIX / 'lib'}", f"-L{libs}", "-Wl,-rpath,$ORIGIN/../../.."]
    with concurrent.futures.ThreadPoolExecutor(COMPILE_JOBS) as pool:
        jobs = []
        for entry in sorted(py_dir.glob(f"_{package}_s.ep.*.c")):
            typesupport = entry.name.split(".ep.")[1].removesuffix(".c")
            jobs.append(
                pool.submit(
                    _shared_library,
                    py_dir / f"{package}_s__{typesupport}.so",
                    [str(entry)],
                    include_flags + python_flags,
                    extension_flags
                    + [
                        f"-l{package}__rosidl_generator_py",
                        f"-l{package}__{typesupport}",
                        own,
                        f"-l{package}__rosidl_typesupport_c",
                        "-lrosidl_runtime_c",
                        "-lrmw",
                        "-lrcutils",
                    ],
                )
            )
        for job in jobs:
            job.result()


def _shared_library(output: pathlib.Path, sources: list[str], include_flags: list[str], link_flags: list[str]) -> None:
    compiler = "g++" if any(source.endswith(".cpp") for source in sources) else "gcc"
    standard = ["-std=c++17"] if compiler == "g++" else ["-std=c11"]
    command = [
        compiler,
        *standard,
        "-O2",
        "-fPIC",
        "-shared",
        "-w",
        *include_flags,
        *sources,
        "-o",
        str(output),
        *link_flags,
    ]
    subprocess.run(command, check=True)


def _install(package: str, work: pathlib.Path, gen: pathlib.Path, libs: pathlib.Path) -> None:
    for library in sorted(libs.glob("*.so")):
        shutil.copy2(library, PREFIX / "lib" / library.name)
    (gen / "py" / package / "__init__.py").touch()
    _replace_tree(gen / "py" / package, SITE_PACKAGES / package, ignore=shutil.ignore_patterns("*.c", "tmp"))
    include = PREFIX / "include" / package / package
    if include.exists():
        shutil.rmtree(include)
    for name in ("c", "typesupport_c", "fastrtps_c", "introspection_c"):
        shutil.copytree(
            gen / name / package,
            include,
            dirs_exist_ok=True,
            ignore=shutil.ignore_patterns("*.c", "*.cpp", "*.json", "tmp"),
        )
    share = PREFIX / "share" / package
    share.mkdir(parents=True, exist_ok=True)
    for relative in _definitions(package):
        target = share / relative.parent
        target.mkdir(exist_ok=True)
        shutil.copy2(INTERFACES / package / relative, target / relative.name)
        shutil.copy2(work / "idl" / relative.with_suffix(".idl"), target / relative.with_suffix(".idl").name)
    for description in (gen / "c" / package).glob("*/*.json"):
        shutil.copy2(description, share / description.parent.name / description.name)
    index = PREFIX / "share" / "ament_index" / "resource_index"
    (index / "packages").mkdir(parents=True, exist_ok=True)
    (index / "packages" / package).write_text("")
    (index / "rosidl_interfaces").mkdir(parents=True, exist_ok=True)
    (index / "rosidl_interfaces" / package).write_text(
        "\n".join(f"{relative.parent.as_posix()}/{relative.name}" for relative in _definitions(package)) + "\n"
    )


def _replace_tree(source: pathlib.Path, target: pathlib.Path, ignore) -> None:
    staging = target.with_name(target.name + ".new")
    if staging.exists():
        shutil.rmtree(staging)
    shutil.copytree(source, staging, ignore=ignore)
    if target.exists():
        shutil.rmtree(target)
    staging.rename(target)


if __name__ == "__main__":
    sys.exit(main())
