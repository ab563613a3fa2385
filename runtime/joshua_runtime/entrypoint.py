"""The one function a generated node entrypoint calls: `run_node(SETTINGS)`.

joshuac writes every node's resolved settings into `OUT/nodes/<node>.py` as a dict literal and
calls `run_node` with it. The dict has these keys (every default already resolved; "" or [] when
a field does not apply to the node type):

    robot, mode, name, type                      str  (type: a NodeType name, or "SIMULATION")
    topic        {"name", "message_type", "qos"} or None
    state_topic  {"name", "message_type", "qos"} or None   (ACTUATOR_SUBSCRIBER present states)
    inputs       [{"name", "message_type", "qos"}, ...]   (INFERENCE / DATA_SUBSCRIBER inputs; QoS
                                                           chosen to match their publishers)
    qos          {"history": "KEEP_LAST"|"KEEP_ALL", "depth": int,
                  "reliability": "RELIABLE"|"BEST_EFFORT", "durability": "VOLATILE"|"TRANSIENT_LOCAL"}
    serial_port str, baud_rate int, device_ids [int], joint_names [str], calibration_file str,
    keep_torque_on_exit bool
    camera_index int, video_source str, width int, height int, rate_hz float, frame_id str
    model_path str, policy_type str, device str, output_format str, output_directory str
    simulation   None

A field that does not apply to the node type holds "", [], 0 (camera_index: -1). The simulation
engine of MODE_SIMULATION (type "SIMULATION") gets only robot, mode, name, type and
    simulation   {"model", "timestep_s", "realtime_factor", "camera", "gl_backend",
                  "simulates": [settings of each replaced hardware node]}

Exit codes (`joshua_core.exit_codes`): 0 clean stop, 1 runtime failure, 2 unusable settings, 3 device
failure, 6 data lost (the node could not save data it had taken in).

Once a node has run, `run_node` ends the process itself (see `end_process`): the DDS library's
teardown at interpreter exit alone takes 0.2-0.4 s, too much for the 0.5 s shutdown contract.
"""

import atexit
import importlib
import os
import sys
import threading

from joshua_core.node_types import spec
from joshua_runtime.errors import JoshuaError, SettingsError

def node_class(node_type: str):
    """Import and return the class that implements a node type (named by the node-type registry)."""
    entry = spec(node_type)
    if entry is None or not entry.runtime_class:
        raise SettingsError(f"no runtime implementation for node type {node_type!r}")
    module_name, class_name = entry.runtime_class.split(":")
    return getattr(importlib.import_module(module_name), class_name)


def end_process(code: int) -> None:
    """Exit like a normal interpreter exit, minus the slow native teardown.

    Non-daemon threads are joined and atexit handlers run, as `sys.exit` would do; then stdio is
    flushed and the process ends with os._exit, skipping interpreter finalization and the C++
    static destructors of the DDS libraries.
    """
    current = threading.current_thread()
    for thread in threading.enumerate():
        if thread is not current and not thread.daemon:
            thread.join()
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code)


def run_node(settings: dict, exit_process: bool = True) -> int:
    """Run the node described by `settings` until SIGINT/SIGTERM.

    Ends the process with the node's exit code (`end_process`); with exit_process=False it
    returns the code instead.
    """
    from joshua_runtime.node import StopRequested, StopSignal, run

    stop = StopSignal().install()  # before the imports: a heavy node may be stopped while loading
    try:
        cls = node_class(settings["type"])
    except StopRequested:
        cls, code = None, 0
    except JoshuaError as exc:
        print(f"{settings.get('name', '?')}: error: {exc}", file=sys.stderr, flush=True)
        cls, code = None, exc.exit_code
    if cls is not None:
        code = run(cls, settings, stop)
    if exit_process:
        end_process(code)
    return code
