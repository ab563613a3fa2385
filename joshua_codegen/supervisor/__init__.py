"""The code of the generated supervisor.py: standard-library modules joined into supervisor_code.py by the emitter.

Conventions that let `joshua_codegen/emitters/supervisor.py` concatenate these modules:
- a module imports only the standard library and, with `from joshua_codegen.supervisor.MODULE import
  NAME, ...` at its top level, other modules of this package; those imports are dropped when joining,
  the standard-library ones are merged into one sorted block at the top of supervisor_code.py;
- every top-level name is unique across the package (the joined file is one namespace, supervisor.py's);
- `robot.py` holds placeholder data only; the emitter writes the robot's real data into supervisor.py,
  which runs supervisor_code.py in its own namespace;
- each module starts with a one-line docstring, which becomes a comment in supervisor_code.py;
- a standard-library module that starting the robot does not need (json, ast, subprocess, traceback) is
  imported inside the functions that use it, in every module, and shutil not at all (argparse, given a
  width, does not load it either): each start pays for importing only what it runs.
"""

# The order the modules are joined in (after the robot's data); each uses only names defined earlier
# at import time.
MODULES = (
    "policy",
    "common",
    "run_mark",
    "build",
    "reload_plan",
    "fd_limit",
    "cgroup_fork",
    "containment",
    "children",
    "guard",
    "node_processes",
    "shm",
    "node",
    "node_starter",
    "discovery_report",
    "notify",
    "preflight",
    "outcome",
    "node_log",
    "poller",
    "control_request",
    "control_socket",
    "control_connection",
    "reload",
    "control",
    "stop_cascade",
    "launching",
    "loop",
    "supervisord_listener",
    "ctl_hosts",
    "ctl",
    "cli",
)
ROBOT_MODULE = "robot"
