"""W102 cpp-backend-ignored: preferred_backend CPP on a node type that has no C++ binary.

What it checks:
    Nodes of the types without a C++ binary ({python_types}) do not ask for `preferred_backend:
    CPP`. The types with one are {cpp_types}: their binaries are built by `make cpp` from the
    node-type registry.

Why it matters:
    These types always run their Python entrypoint (CUSTOM: its executable), so the preference has
    no effect and misleads readers: the robot would not run the C++ node it seems to ask for.

Example:
    node {
      type: CAMERA_PUBLISHER
      preferred_backend: CPP     # warning: CAMERA_PUBLISHER has no C++ binary and always runs ...
    }
"""

from joshua_codegen import defaults
from joshua_codegen.diagnostics import WARNING
from joshua_codegen.rules.context import Finding
from joshua_core.schema import robot_config_pb2 as pb

TYPE_LISTS = {"python_types": lambda entry: not entry.binary, "cpp_types": lambda entry: bool(entry.binary)}
CODE = "W102"
NAME = "cpp-backend-ignored"
SEVERITY = WARNING
STAGE = "check"


def check(ctx):
    for view in ctx.typed_nodes:
        node = view.node
        if node.type in defaults.ALWAYS_PYTHON and node.preferred_backend == pb.CPP:
            runs = "its executable" if defaults.entry(node).declares_topics else "its Python entrypoint"
            yield Finding(
                view.at("preferred_backend"),
                f"{defaults.type_name(node.type)} has no C++ binary and always runs {runs}; "
                "preferred_backend CPP is ignored",
            )
