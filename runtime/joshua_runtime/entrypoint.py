"""The one function a generated node entrypoint calls: `run_node(SETTINGS)`.

joshuac writes every node's resolved settings into `OUT/nodes/<node>.py` as the literal form of a
NodeSettings message (the settings contract: proto/joshua/v1/node_settings.proto, read through
joshua_core.settings); `run_node` parses it back into that message, refusing settings of another
format version, and runs the class the node-type registry names for the node's type.

Exit codes (`joshua_core.exit_codes`): 0 clean stop, 1 runtime failure, 2 unusable settings, 3 device
failure, 6 data lost (the node could not save data it had taken in).

A node that crashes in native code (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT) prints the Python stack of
each of its threads first (faulthandler), so the supervisor's log says where.

Once a node has run, `run_node` ends the process itself (process_end.py): the DDS library's
teardown at interpreter exit alone takes 0.2-0.4 s, too much for the 0.5 s shutdown contract.
"""

import faulthandler
import importlib
import sys

from joshua_core.node_types import spec
from joshua_core.settings import SettingsFormatError
from joshua_core.settings import parse as parse_settings
from joshua_runtime.errors import JoshuaError, SettingsError
from joshua_runtime.process_end import end_process


def node_class(node_type: str):
    """Import and return the class that implements a node type (named by the node-type registry)."""
    entry = spec(node_type)
    if entry is None or not entry.runtime_class:
        raise SettingsError(f"no runtime implementation for node type {node_type!r}")
    module_name, class_name = entry.runtime_class.split(":")
    return getattr(importlib.import_module(module_name), class_name)


def run_node(literal: dict, exit_process: bool = True) -> int:
    """Run the node described by the settings literal of a generated entrypoint until SIGINT/SIGTERM.

    Ends the process with the node's exit code (`end_process`); with exit_process=False it
    returns the code instead.
    """
    from joshua_runtime.stop_signal import StopRequested, StopSignal

    faulthandler.enable()
    stop = StopSignal().install()  # before the imports: a node may be stopped while it loads rclpy or more
    name = literal.get("name", "?") if isinstance(literal, dict) else "?"
    try:
        from joshua_runtime.node import run

        settings = parse_settings(literal)
        cls = node_class(settings.type)
    except StopRequested:
        cls, code = None, 0
    except SettingsFormatError as exc:
        print(f"{name}: error: {exc}", file=sys.stderr, flush=True)
        cls, code = None, SettingsError.exit_code
    except JoshuaError as exc:
        print(f"{name}: error: {exc}", file=sys.stderr, flush=True)
        cls, code = None, exc.exit_code
    if cls is not None:
        code = run(cls, settings, stop)
    if exit_process:
        end_process(code)
    return code
