"""W104 relative-data-path: a file or directory a node reads or writes is given as a relative path.

What it checks:
    `simulation.model` (unless `builtin:`), and the nodes' `calibration_file`, `output_directory`,
    `model_path` (unless `registry:`) and `video_source` (unless a URL) are absolute paths.

Why it matters:
    A relative path is resolved from the working directory of whoever starts the node: the
    directory supervisor.py was started from, but the output directory under systemd and
    supervisord. The same description would then read or write different files.

Example:
    node {
      type: DATA_SUBSCRIBER
      output_directory: "episodes"     # warning: output_directory "episodes" is a relative path
    }
"""

from joshua_codegen.diagnostics import WARNING
from joshua_codegen.positions import ROBOT
from joshua_codegen.rules.context import Finding
from joshua_core.models import BUILTIN_PREFIX, REGISTRY_PREFIX

CODE = "W104"
NAME = "relative-data-path"
SEVERITY = WARNING
STAGE = "check"
ADVICE = "it depends on the working directory of the process manager; use an absolute path"
NODE_FIELDS = ("calibration_file", "output_directory", "model_path", "video_source")
NOT_PATHS = (BUILTIN_PREFIX, REGISTRY_PREFIX)


def _relative(value: str) -> bool:
    return bool(value) and not value.startswith("/") and not value.startswith(NOT_PATHS) and "://" not in value


def check(ctx):
    model = ctx.config.simulation.model
    if _relative(model):
        yield Finding(ROBOT + ("simulation", "model"), f'simulation model "{model}" is a relative path; {ADVICE}')
    for view in ctx.typed_nodes:
        for field in NODE_FIELDS:
            value = getattr(view.node, field)
            if _relative(value):
                yield Finding(view.at(field), f'{field} "{value}" is a relative path; {ADVICE}')
