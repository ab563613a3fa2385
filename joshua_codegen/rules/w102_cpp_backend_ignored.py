"""W102 cpp-backend-ignored: preferred_backend CPP on a node type that always runs Python.

What it checks:
    INFERENCE, DATA_SUBSCRIBER, MOCK_* and CUSTOM nodes do not ask for `preferred_backend: CPP`.

Why it matters:
    These types have no C++ implementation, so the preference has no effect and misleads readers.

Example:
    node {
      type: INFERENCE
      preferred_backend: CPP     # warning: INFERENCE always runs its Python entrypoint
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import WARNING
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

CODE = "W102"
NAME = "cpp-backend-ignored"
SEVERITY = WARNING
STAGE = "check"


def check(ctx):
    for view in ctx.typed_nodes:
        node = view.node
        if node.type in defaults.ALWAYS_PYTHON and node.preferred_backend == pb.CPP:
            runs = "its executable" if node.type == pb.CUSTOM else "its Python entrypoint"
            yield Finding(
                view.at("preferred_backend"),
                f"{defaults.type_name(node.type)} always runs {runs}; preferred_backend CPP is ignored",
            )
