"""Node settings for the runtime tests, written by the real compiler from a small description text.

Tests that run nodes use these instead of settings dicts written by hand, so that a node's settings
are exactly what a generated entrypoint passes to `run_node`: a change to the compiler's output
that the runtime does not follow breaks the runtime tests too. Importable by every test as
testsupport.compiled_settings: pytest puts the repository root on sys.path for its conftest.py.
"""

from collections.abc import Sequence

import pytest

from joshua_codegen.compile import DescriptionError, node_settings

# The file name diagnostics of a description given as text are reported against.
DESCRIPTION_PATH = "test_description.pbtxt"
TEST_ROBOT = "test_robot"


def compiled_settings(
    description_text: str, overrides: Sequence[str] = (), path: str = DESCRIPTION_PATH
) -> dict[str, dict]:
    """Every node's settings by node name, and the simulation engine's under its process name.

    `overrides` are `--set` values (`NODE.serial_port=/dev/pts/3`). A description with errors fails
    the test with joshuac's diagnostics; warnings are allowed, as they are for `joshuac build`.
    Every dict is its own copy, so a test may change one node's settings freely.
    """
    try:
        return node_settings(description_text, overrides, path)
    except DescriptionError as exc:
        pytest.fail(f"the test description does not compile:\n{exc}", pytrace=False)


def compiled_node(node_fields: str, overrides: Sequence[str] = ()) -> dict:
    """The settings of the only node of a teleoperated robot, given as the fields inside its `node { }` block."""
    text = f'robot_config {{\n  name: "{TEST_ROBOT}"\n  mode: MODE_TELEOPERATION\n  node {{ {node_fields} }}\n}}\n'
    (settings,) = compiled_settings(text, overrides).values()
    return settings
