"""Node settings for the runtime tests, written by the real compiler from a small description text.

Tests that run nodes use these instead of settings dicts written by hand, so that a node's settings
are exactly what a generated entrypoint passes to `run_node`: a change to the compiler's output
that the runtime does not follow breaks the runtime tests too. Importable by every test, as pytest
puts this directory on sys.path for the conftest.py beside it.
"""

import copy
from collections.abc import Sequence

import pytest

from joshua_codegen.check import check_text
from joshua_codegen.diagnostics import format_text
from joshua_codegen.plan import plan

# The file name diagnostics of a description given as text are reported against.
DESCRIPTION_PATH = "test_description.pbtxt"
TEST_ROBOT = "test_robot"


def compiled_settings(description_text: str, overrides: Sequence[str] = (),
                      path: str = DESCRIPTION_PATH) -> dict[str, dict]:
    """Every node's settings by node name, and the simulation engine's under its process name.

    `overrides` are `--set` values (`NODE.serial_port=/dev/pts/3`). A description with errors fails
    the test with joshuac's diagnostics; warnings are allowed, as they are for `joshuac build`.
    """
    result = check_text(path, description_text, overrides)
    if result.has_errors or result.description is None:
        pytest.fail(f"the test description does not compile:\n{format_text(result.diagnostics, result.sources)}",
                    pytrace=False)
    robot = plan(result.description, path)
    settings = {node.name: node.settings for node in robot.nodes}
    for process in robot.processes:
        if process.node_type == "SIMULATION":
            settings[process.name] = robot.process_settings(process)
    # Each its own copy: the engine's settings hold the very dicts of the nodes it simulates, and a
    # test that changes one node's settings must not change the engine's too.
    return {name: copy.deepcopy(value) for name, value in settings.items()}


def compiled_node(node_fields: str, overrides: Sequence[str] = ()) -> dict:
    """The settings of the only node of a teleoperated robot, given as the fields inside its `node { }` block."""
    text = f'robot_config {{\n  name: "{TEST_ROBOT}"\n  mode: MODE_TELEOPERATION\n  node {{ {node_fields} }}\n}}\n'
    (settings,) = compiled_settings(text, overrides).values()
    return settings
