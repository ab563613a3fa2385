"""`joshuac build FLEET -o OUT`: one release per robot, and the Ansible files that roll them out.

    OUT/robots/<robot>/          the robot's complete build for --prefix /opt/joshua/current, with its bundle,
                                 its own stamp and, with --sign, the stamp's signature: one release (for a
                                 robot on several computers, each OUT/robots/<robot>/hosts/<host>/ is one)
    OUT/ansible/inventory.yml    the robots in rollout order, their addresses and releases, the rollout settings
    OUT/ansible/deploy.yml       copy, verify, install, switch, gate (rollback on failure), robot by robot
    OUT/ansible/rollback.yml     back to each robot's previous release
    OUT/ansible/files/           the scripts those playbooks run on the robots

A release is named by the first 12 hex digits of the SHA-256 of its stamp (the `build` its supervisor
reports), so the same description with the same overrides is the same release on every build.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

from joshua_codegen.bundle import bundle_files
from joshua_codegen.fleet.check import FLEET_PREFIX, RELEASE_PYTHON, ROBOT_ROOT, FleetCheckResult, FleetMember
from joshua_codegen.ownership import STAMP
from joshua_codegen.plan import plan
from joshua_codegen.render import host_path, render
from joshua_codegen.signing import DEFAULT_RELEASE_KEY
from joshua_codegen.write import stamped
from joshua_core.schema import fleet_config_pb2 as pb

ROBOTS_DIR = "robots"
RELEASE_DIGITS = 12
DEFAULT_CANARY = 1
DEFAULT_BATCH = 5
DEFAULT_HEALTH_TIMEOUT_S = 120.0
START_METHODS = {pb.START_METHOD_UNSPECIFIED: "systemd", pb.START_SYSTEMD: "systemd", pb.START_SUPERVISOR: "supervisor"}
ON_FAILURE = {pb.ON_FAILURE_UNSPECIFIED: "stop", pb.ON_FAILURE_STOP: "stop", pb.ON_FAILURE_CONTINUE: "continue"}


@dataclass(frozen=True)
class Release:
    """One computer of the fleet with the release built for it: a robot, or one host of a robot on several."""

    robot: str
    host: str  # the host's name for a robot on several computers, else ""
    address: str
    ssh_user: str  # "" for the deploying user's SSH default
    ssh_port: int | None
    release: str  # 12 hex digits of the SHA-256 of its stamp
    python: str  # the interpreter of its nodes (and of supervisor.py)
    install: bool  # the rollout makes the release's Python environment (its nodes run RELEASE_PYTHON)
    files: dict  # relative path in the release -> content, stamp (and signature) included

    @property
    def name(self) -> str:
        """Its name in the inventory: the robot's, or `<robot>.<host>`."""
        return f"{self.robot}.{self.host}" if self.host else self.robot

    @property
    def control(self) -> str:
        """What names its supervisor's control socket (`<robot>.<host>` on a robot of several hosts)."""
        return self.name

    @property
    def directory(self) -> str:
        robot = f"{ROBOTS_DIR}/{self.robot}"
        return f"{robot}/{host_path(self.host)}" if self.host else robot


@dataclass(frozen=True)
class Fleet:
    name: str
    source: str  # the fleet file, as given
    root: str
    start: str  # "systemd" | "supervisor"
    release_key: str
    canary: int
    batch: int
    health_timeout_s: float
    on_failure: str  # "stop" | "continue"
    builds: tuple[tuple[dict, list[Release]], ...]  # per robot: every file of its build, and its releases

    @property
    def releases(self) -> list[Release]:
        """Every computer's release, robot by robot in the fleet's order."""
        return [release for _, releases in self.builds for release in releases]


def release_id(files: dict) -> str:
    return hashlib.sha256(files[STAMP].encode("utf-8")).hexdigest()[:RELEASE_DIGITS]


def robot_releases(member: FleetMember, signer=None) -> tuple[dict, list[Release]]:
    """(every file of the robot's build, its releases: one, or one per host of a robot on several)."""
    check = member.check
    robot = check.robot or plan(check.description, member.description_path)
    files = stamped({**render(robot, FLEET_PREFIX), **bundle_files(robot)}, signer)
    entry = member.entry
    common = dict(
        robot=entry.name,
        ssh_user=entry.ssh_user,
        ssh_port=entry.ssh_port if entry.HasField("ssh_port") else None,
        python=robot.python_executable,
        install=robot.python_executable in (RELEASE_PYTHON, RELEASE_PYTHON.removesuffix("3")),
    )
    if not robot.hosts:
        return files, [Release(host="", address=entry.address, release=release_id(files), files=files, **common)]
    releases = []
    for host in robot.hosts:
        prefix = host_path(host.name) + "/"
        part = {path[len(prefix) :]: content for path, content in files.items() if path.startswith(prefix)}
        releases.append(Release(host=host.name, address=host.address, release=release_id(part), files=part, **common))
    return files, releases


def plan_fleet(result: FleetCheckResult, signer=None) -> Fleet:
    """The fleet's releases (each robot built, bundled, stamped and signed); `result` must have no error."""
    config = result.fleet
    rollout = config.rollout
    return Fleet(
        name=config.name,
        source=result.path,
        root=ROBOT_ROOT,
        start=START_METHODS[config.start],
        release_key=config.release_key or DEFAULT_RELEASE_KEY,
        canary=rollout.canary if rollout.HasField("canary") else DEFAULT_CANARY,
        batch=rollout.batch if rollout.HasField("batch") else DEFAULT_BATCH,
        health_timeout_s=rollout.health_timeout_s if rollout.HasField("health_timeout_s") else DEFAULT_HEALTH_TIMEOUT_S,
        on_failure=ON_FAILURE[rollout.on_failure],
        builds=tuple(robot_releases(member, signer) for member in result.members),
    )


def fleet_files(fleet: Fleet) -> dict:
    """Every file of the fleet's output directory, by path relative to it (its own stamp aside)."""
    from joshua_codegen.fleet.ansible import ansible_files

    files = {}
    for build, releases in fleet.builds:
        robot = releases[0].robot
        files.update({f"{ROBOTS_DIR}/{robot}/{path}": content for path, content in build.items()})
    files.update(ansible_files(fleet))
    return dict(sorted(files.items()))
