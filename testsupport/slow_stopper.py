"""A node program that stops slowly and asks its process manager for more time meanwhile (EXTEND_TIMEOUT_USEC), as
the recorder does while it saves: `slow_stopper_node` is a CUSTOM node of a description that runs it."""

import sys
from pathlib import Path

from testsupport.description_text import quoted

PYTHON_PROGRAM = Path(__file__).with_name("slow_stopper_program.py")


def slow_stopper_node(
    directory: Path, name: str, extension_s: float, every_s: float, asking_s: float, then: str, fields: str = ""
) -> str:
    """The node `name`: on SIGINT it asks for `extension_s` more seconds every `every_s` until `asking_s` have passed,
    then exits 0 (`then="exit"`) or keeps running without asking (`then="stay"`); SIGTERM ends it. It writes what
    happens to it to DIRECTORY/events.log ("NAME PID TEXT" lines). `fields`: more fields of the node (its host)."""
    args = [
        str(PYTHON_PROGRAM),
        str(directory / "events.log"),
        name,
        str(extension_s),
        str(every_s),
        str(asking_s),
        then,
    ]
    return (
        f'node {{ name: "{name}" type: CUSTOM executable: "{sys.executable}" '
        f"args: [{', '.join(map(quoted, args))}] {fields} }}"
    )
