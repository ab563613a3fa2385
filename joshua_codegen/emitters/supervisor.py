"""supervisor.py: the standalone process supervisor of a robot (fork/exec, restarts, signal cascade).

supervisor.py is the header of `supervisor.py.j2` (usage and exit codes), the robot's data in place of
`joshua_codegen/supervisor/robot.py`, then a few lines that run the code of supervisor_code.py in its
namespace, compiled once and then kept in the user's cache (compiling 4,000 lines costs a start about 20 ms).
supervisor_code.py holds the modules of `joshua_codegen.supervisor` joined in the order of its `MODULES` (see
that package's docstring for the conventions joining relies on), the same for every robot.
"""

import ast
import hashlib
from functools import cache
from pathlib import Path

from joshua_codegen import supervisor as package
from joshua_codegen.emitters import fastdds, process_launch, supervisord
from joshua_codegen.model import Process, Robot
from joshua_codegen.ownership import STAMP
from joshua_codegen.render import SUPERVISOR_CODE_PATH, Context, template
from joshua_core import exit_codes
from joshua_core.models import REGISTRY_DEFAULT_ROOT, REGISTRY_ENTRY_FILE, REGISTRY_ENV, REGISTRY_PREFIX
from joshua_core.settings import FORMAT_VERSION

SUPERVISOR_PATH = "supervisor.py"
CODE_PATH = SUPERVISOR_CODE_PATH
# Where supervisor.py keeps its code compiled, under the user's cache directory ($XDG_CACHE_HOME, else ~/.cache).
BYTECODE_CACHE = "joshua/supervisor"
# How the generated launchers run supervisor.py: it needs only the standard library, so without `site` (the
# environment's .pth files, the ROS wheels' bootstrapper among them) it starts about 30 ms sooner.
INTERPRETER_FLAGS = ("-S",)
PACKAGE_DIR = Path(package.__file__).parent
PACKAGE_PREFIX = f"{package.__name__}."
SUPERVISOR_CODE_DIGITS = 16


def process_data(robot: Robot, process: Process) -> dict:
    """What the supervisor needs to launch and check one node, as plain data."""
    settings = robot.process_settings(process)
    model_path = settings.model_path
    return {
        "name": process.name,
        "type": process.node_type,
        "kind": process.kind,
        "entrypoint": process.entrypoint,
        "executable": process.executable,
        "args": list(process.args),
        "cpp_binary": process.cpp_binary,
        "cpp_args": list(process.cpp_args),
        "restart": process.restart,
        "max_restarts": process.max_restarts,
        "critical": process.critical,
        "env": dict(process.env),
        "fastdds_profile": fastdds.profile_path(process),
        "devices": [{"kind": device.kind, "path": device.path} for device in process.devices],
        "model_reference": model_path if model_path.startswith(REGISTRY_PREFIX) else "",
        "output_directory": settings.output_directory,
        **({"starts_first": True} if process.starts_first else {}),
        "inputs": list(process.inputs),
    }


def supervisor_data(robot: Robot) -> dict:
    """The one literal the generated supervisor reads; paths are relative to its directory. One host's
    supervisor of a robot on several also knows its host (which names its control socket) and the Discovery
    Server its agent watches (shown in `ctl status`)."""
    server = robot.discovery if robot.host else None
    return {
        "name": robot.name,
        **({"host": robot.host, "hosts": [host.name for host in robot.hosts]} if robot.host else {}),
        **({"discovery_server": f"{server.address}:{server.port}"} if server else {}),
        "supervisor_code": supervisor_code(),
        "env": process_launch.robot_environment(robot),
        "cpp_bin_dir": robot.cpp_bin_dir,
        "fastdds_profile_variable": process_launch.FASTDDS_PROFILE_VARIABLE,
        "supervisord_group": supervisord.group_name(robot),
        "stamp_file": STAMP,
        "model_registry": {
            "prefix": REGISTRY_PREFIX,
            "variable": REGISTRY_ENV,
            "default_root": REGISTRY_DEFAULT_ROOT,
            "entry_file": REGISTRY_ENTRY_FILE,
        },
        "node_exit_codes": {"settings": exit_codes.NODE_EXIT_SETTINGS, "data_lost": exit_codes.NODE_EXIT_DATA_LOST},
        "settings_format_version": FORMAT_VERSION,
        "processes": [process_data(robot, process) for process in robot.processes],
    }


def is_package_import(node: ast.stmt) -> bool:
    return isinstance(node, ast.ImportFrom) and (node.module or "").startswith(PACKAGE_PREFIX)


@cache
def module_parts(name: str) -> tuple[tuple[str, ...], str]:
    """(standard-library import lines, code) of one package module: its docstring becomes a comment,
    its imports are taken out (the package's own are dropped)."""
    source = (PACKAGE_DIR / f"{name}.py").read_text(encoding="utf-8")
    tree = ast.parse(source)
    lines = source.splitlines()
    removed: set[int] = set()
    imports = []
    docstring = ast.get_docstring(tree, clean=True) or ""
    for node in tree.body:
        is_docstring = node is tree.body[0] and docstring and isinstance(node, ast.Expr)
        if is_docstring or isinstance(node, (ast.Import, ast.ImportFrom)):
            removed.update(range(node.lineno - 1, node.end_lineno or node.lineno))
            if isinstance(node, (ast.Import, ast.ImportFrom)) and not is_package_import(node):
                # Slicing the lines, not ast.get_source_segment, which splits the whole source per call.
                imports.append("\n".join(lines[node.lineno - 1 : node.end_lineno or node.lineno]))
    kept = [line for number, line in enumerate(lines) if number not in removed]
    code = "\n".join(kept).strip("\n")
    return tuple(imports), f"# {docstring}\n\n\n{code}\n"


@cache
def joined_code() -> tuple[str, str]:
    """(the merged standard-library import block, the modules' code in `MODULES` order)."""
    imports: set[str] = set()
    codes = []
    for name in package.MODULES:
        module_imports, code = module_parts(name)
        imports.update(module_imports)
        codes.append(code)
    ordered = sorted(imports, key=lambda line: (line.startswith("from "), line))
    return "\n".join(ordered) + "\n", "\n\n".join(codes)


@cache
def supervisor_code() -> str:
    """What tells one version of the supervisor's code from another (a reload takes only builds of its own code):
    the first SUPERVISOR_CODE_DIGITS hex digits of the SHA-256 of the joined modules."""
    imports, code = joined_code()
    return hashlib.sha256((imports + code).encode()).hexdigest()[:SUPERVISOR_CODE_DIGITS]


@cache
def code_file() -> str:
    imports, code = joined_code()
    return template("supervisor_code.py.j2", imports=imports, code=code)


def emit(robot: Robot, context: Context) -> dict[str, str]:
    text = template(
        "supervisor.py.j2", robot=robot, data=supervisor_data(robot), code_path=CODE_PATH, bytecode_cache=BYTECODE_CACHE
    )
    return {SUPERVISOR_PATH: text, CODE_PATH: code_file()}
