"""Which robots a rollout takes and in what order: canaries first, then batches, in the inventory's order."""

import fnmatch

from joshua_runtime.errors import SettingsError
from joshua_runtime.rollout.inventory import Robot


def _matches(robot: Robot, pattern: str) -> bool:
    return fnmatch.fnmatchcase(robot.robot, pattern) or fnmatch.fnmatchcase(robot.name, pattern)


def selected(robots: tuple[Robot, ...], limit: str | None) -> list[Robot]:
    """The robots matching `limit`: comma-separated robot names or shell patterns (`arm_*`; `split.gpu` for
    one host of a robot on several); a pattern starting with `!` excludes what it matches. Without a
    limit, every robot."""
    if not limit:
        return list(robots)
    patterns = [part.strip() for part in limit.split(",") if part.strip()]
    included = [p for p in patterns if not p.startswith("!")] or ["*"]
    excluded = [p[1:] for p in patterns if p.startswith("!")]
    for pattern in included + excluded:
        if not any(_matches(robot, pattern) for robot in robots):
            raise SettingsError(f"--limit: no robot of the fleet matches {pattern!r}")
    chosen = [
        robot
        for robot in robots
        if any(_matches(robot, p) for p in included) and not any(_matches(robot, p) for p in excluded)
    ]
    if not chosen:
        raise SettingsError(f"--limit {limit!r} leaves no robot")
    return chosen


def batches(robots: list[Robot], canary: int, batch: int) -> list[tuple[str, list[Robot]]]:
    """[("canary", the first `canary` robots), ("batch 1", the next `batch`), ...], counted in robots, each
    with all its computers; empty parts left out."""
    if canary < 0 or batch < 1:
        raise SettingsError(f"--canary must be 0 or more and --batch 1 or more (they are {canary} and {batch})")
    by_robot: dict[str, list[Robot]] = {}
    for robot in robots:
        by_robot.setdefault(robot.robot, []).append(robot)
    groups = list(by_robot.values())
    parts = [("canary", groups[:canary])] if canary else []
    rest = groups[canary:]
    parts += [(f"batch {n + 1}", rest[i : i + batch]) for n, i in enumerate(range(0, len(rest), batch))]
    return [(label, [robot for group in part for robot in group]) for label, part in parts if part]
