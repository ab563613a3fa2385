"""What a robot's name looks like: the compiler checks descriptions against it (E101), and the fleet view
the names robots publish under."""

import re

MAX_ROBOT_NAME_LENGTH = 64
ROBOT_NAME = re.compile(r"[a-z][a-z0-9_]*")


def is_robot_name(text: str) -> bool:
    """True for lower-case letters, digits and underscores, starting with a letter, at most 64 characters."""
    return len(text) <= MAX_ROBOT_NAME_LENGTH and ROBOT_NAME.fullmatch(text) is not None


def suggested_robot_name(name: str) -> str | None:
    """A valid robot name close to `name` (lower case, underscores for the rest), or None when there is none."""
    candidate = re.sub(r"[^a-z0-9_]+", "_", name.lower()).strip("_")
    candidate = re.sub(r"^[0-9_]+", "", candidate)[:MAX_ROBOT_NAME_LENGTH]
    return candidate if ROBOT_NAME.fullmatch(candidate) else None
