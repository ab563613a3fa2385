"""`make image CONFIG=...`: a robot's container image, built with podman (or docker) in the user's own storage.

    .venv/bin/python scripts/image.py CONFIG [--base IMAGE] [--engine podman|docker] [--set KEY=VALUE ...]
        [--context DIR]

Writes the image's build context with `joshuac build CONFIG -o DIR --image` (DIR: build/image/<config name>),
then builds it tagged `localhost/joshua/<robot>:<stamp hash>` (the first 12 hex digits of the
SHA-256 of OUT/.joshuac-stamp, so the tag changes with any file of the build) and
`localhost/joshua/<robot>:latest`. When this machine's CA bundle is found (SSL_CERT_FILE, else
OpenSSL's default file), pip in the build trusts it: it is passed as the build secret
`ca-certificates`, mounted for the install step only and never stored in the image. With podman
the build's steps use the host's network, so no bridge is set up for them.
"""

import argparse
import hashlib
import json
import os
import shutil
import ssl
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
JOSHUAC = ROOT / ".venv" / "bin" / "joshuac"
CONTEXT_ROOT = ROOT / "build" / "image"
ENGINES = ("podman", "docker")
REPOSITORY = "localhost/joshua/{robot}"
TAG_DIGITS = 12
STAMP = ".joshuac-stamp"
CA_SECRET = "ca-certificates"
EXIT_NO_ENGINE = 3
INSTALL_HINT = (
    "install one: podman (Debian and Ubuntu: apt install podman runc catatonit; `make setup` does) "
    "or Docker Engine with BuildKit (docker build --secret)"
)


def choose_engine(requested: str | None) -> str | None:
    """The engine's program: the one asked for, else podman, else docker; None when none is installed."""
    for name in (requested,) if requested else ENGINES:
        if shutil.which(name):
            return name
    return None


def stamp_tag(out: Path) -> str:
    """The tag of a build: the start of the SHA-256 of its stamp, which lists every file with its own hash."""
    return hashlib.sha256((out / STAMP).read_bytes()).hexdigest()[:TAG_DIGITS]


def ca_bundle() -> Path | None:
    """The CA bundle this machine's TLS clients trust, when there is one."""
    paths = ssl.get_default_verify_paths()
    for candidate in (os.environ.get("SSL_CERT_FILE"), paths.cafile, paths.openssl_cafile):
        if candidate and Path(candidate).is_file():
            return Path(candidate)
    return None


def build_command(engine: str, out: Path, tags: list[str], base: str | None) -> list[str]:
    """The build command of the context `out`."""
    command = [engine, "build", "--file", str(out / "Containerfile")]
    for tag in tags:
        command += ["--tag", tag]
    if base:
        command += ["--build-arg", f"BASE={base}"]
    bundle = ca_bundle()
    if bundle is not None:
        command += ["--secret", f"id={CA_SECRET},src={bundle}"]
    if Path(engine).name == "podman":
        command += ["--network", "host"]
    return [*command, str(out)]


def robot_name(out: Path) -> str:
    return json.loads((out / "manifest.json").read_text())["robot"]["name"]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("config", type=Path, help="the robot's description (.pbtxt)")
    parser.add_argument("--base", help="base image (default: the Containerfile's, debian:bookworm-slim)")
    parser.add_argument("--engine", choices=ENGINES, help="podman or docker (default: podman when installed)")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--context", type=Path, help="where the build context is written (default build/image/NAME)")
    args = parser.parse_args(argv)

    engine = choose_engine(args.engine)
    if engine is None:
        missing = f"{args.engine} is not installed" if args.engine else "neither podman nor docker is installed"
        print(f"make image: {missing}; {INSTALL_HINT}", file=sys.stderr)
        return EXIT_NO_ENGINE
    out = args.context or CONTEXT_ROOT / args.config.stem
    overrides = [word for override in args.overrides for word in ("--set", override)]
    built = subprocess.run([str(JOSHUAC), "build", str(args.config), "-o", str(out), "--image", *overrides])
    if built.returncode != 0:
        return built.returncode
    repository = REPOSITORY.format(robot=robot_name(out))
    tag = f"{repository}:{stamp_tag(out)}"
    done = subprocess.run(build_command(engine, out, [tag, f"{repository}:latest"], args.base))
    if done.returncode != 0:
        print(f"make image: {engine} build failed (exit code {done.returncode})", file=sys.stderr)
        return done.returncode
    print(f"make image: built {tag} (also {repository}:latest) from {out}")
    print(f"make image: run it: {' '.join(run_command(engine, args.config, args.overrides, tag))}")
    return 0


def run_command(engine: str, config: Path, overrides: list[str], tag: str) -> list[str]:
    """How the image is run: its stop timeout, and the devices and files its robot needs."""
    from joshua_codegen.compile import compile_file
    from joshua_codegen.emitters.containerfile import run_options, stop_timeout_s

    robot = compile_file(str(config), overrides).robot
    options = [item.option for item in run_options(robot)]
    return [engine, "run", "--rm", "--stop-timeout", str(stop_timeout_s(robot)), *options, tag]


if __name__ == "__main__":
    sys.exit(main())
