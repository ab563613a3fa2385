"""E119 path-too-long: a path with a component over 255 bytes, or longer than 4095 bytes in all.

What it checks:
    Programs (`executable`, `python_executable`), `cpp_bin_dir`, `simulation.model` and the nodes'
    `serial_port`, `video_source`, `calibration_file`, `model_path` and `output_directory`, when
    they are paths (not `builtin:`, `registry:` or a URL): no component (the text between two
    `/`) is longer than 255 bytes in UTF-8 (NAME_MAX) and the whole path at most 4095 (PATH_MAX).

Why it matters:
    No Linux file system holds such a name: opening, creating or executing the path fails with
    ENAMETOOLONG when the node starts, and systemd refuses such paths in unit files.

Example:
    node {
      output_directory: "/data/aaaa…(300 letters)"   # error: a component of 300 bytes; the limit is 255
    }
"""

from joshua_codegen.diagnostics import ERROR
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.models import BUILTIN_PREFIX, REGISTRY_PREFIX

CODE = "E119"
NAME = "path-too-long"
SEVERITY = ERROR
STAGE = "check"
NAME_MAX = 255  # bytes of one path component
PATH_MAX = 4096  # bytes of a whole path, its terminating NUL included
NODE_FIELDS = ("executable", "serial_port", "video_source", "calibration_file", "model_path", "output_directory")
NOT_PATHS = (BUILTIN_PREFIX, REGISTRY_PREFIX)


def path_problem(path: str) -> str | None:
    """Why a path cannot exist on Linux, or None."""
    if not path or path.startswith(NOT_PATHS) or "://" in path:
        return None
    size = len(path.encode("utf-8"))
    if size >= PATH_MAX:
        return f"is {size} bytes long; a path holds at most {PATH_MAX - 1}"
    longest = max(path.split("/"), key=lambda part: len(part.encode("utf-8")))
    length = len(longest.encode("utf-8"))
    if length > NAME_MAX:
        return f'has a component of {length} bytes ("{longest[:20]}..."); a file name holds at most {NAME_MAX}'
    return None


def check(ctx):
    config = ctx.config
    paths = [(ROBOT + (field,), field, getattr(config, field)) for field in ("python_executable", "cpp_bin_dir")]
    paths.append((ROBOT + ("simulation", "model"), "simulation model", config.simulation.model))
    paths += [(view.at(field), field, getattr(view.node, field)) for view in ctx.typed_nodes for field in NODE_FIELDS]
    for at, field, path in paths:
        problem = path_problem(path)
        if problem is not None:
            yield Finding(at, f"{field} {problem}")
