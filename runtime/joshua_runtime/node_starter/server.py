"""The node starter's process: import the node types, say ready, then fork one node per request."""

import argparse
import array
import importlib
import inspect
import os
import select
import signal
import socket
import sys

from joshua_runtime.node_starter.fork_hooks import lttng_fork_hooks
from joshua_runtime.node_starter.node_process import NodeRequest, become_node
from joshua_runtime.process_end import end_process

# The interfaces of the topics every node makes by itself (parameter events; ros_node.py leaves out its services).
ROS_NODE_INTERFACES = ("rcl_interfaces.msg",)
SERVICE_PARTS = ("Request", "Response", "Event")
REQUEST_BYTES = 1 << 20  # a node's environment and paths; the supervisor sends far less
FD_BYTES = socket.CMSG_SPACE(array.array("i").itemsize)


def preload(node_types: list[str]) -> None:
    """Import what the nodes of these types import before they run; a type that fails to import is left to its
    node, which reports the error itself when it starts."""
    import rclpy  # noqa: F401 (imported for the nodes forked later)

    from joshua_runtime.entrypoint import node_class
    from joshua_runtime.node import run  # noqa: F401 (imported for the nodes forked later)

    for node_type in node_types:
        try:
            node_class(node_type)
        except Exception:  # noqa: BLE001,S112 (the node itself says what is wrong)
            continue
    import_type_supports()
    map_modules_to_files()


def import_type_supports() -> None:
    """Load the type support of every message and service class imported so far, and of those rclpy's nodes use
    themselves (parameter events). A node loads them when it first makes a publisher, subscription or
    service: the modules of rosidl's parser with its grammar, a C extension per package, about 60 ms of CPU."""
    for name in ROS_NODE_INTERFACES:
        importlib.import_module(name)
    for name, module in list(sys.modules.items()):
        if module is None or not name.endswith((".msg", ".srv")):
            continue
        for value in list(vars(module).values()):
            for interface in (value, *(getattr(value, part, None) for part in SERVICE_PARTS)):
                load = getattr(type(interface), "__import_type_support__", None)
                if load is not None and isinstance(interface, type):
                    load()


def map_modules_to_files() -> None:
    """Let inspect map every module imported so far to its file. rclpy's logger looks up its caller's source
    (inspect.getframeinfo) on every call, and the first lookup in a process maps every loaded module, about
    0.1 s of CPU; mapped here once, the nodes inherit the map."""
    inspect.getframeinfo(inspect.currentframe())


def receive(channel: socket.socket) -> tuple[bytes, int | None]:
    """One request and the descriptor that came with it; b"" when the supervisor closed the socket."""
    message, ancillary, _, _ = channel.recvmsg(REQUEST_BYTES, FD_BYTES)
    descriptors = array.array("i")
    for level, kind, data in ancillary:
        if level == socket.SOL_SOCKET and kind == socket.SCM_RIGHTS:
            descriptors.frombytes(data[: len(data) - len(data) % descriptors.itemsize])
    return message, (descriptors[0] if descriptors else None)


def start_node(channel: socket.socket, request: NodeRequest, output: int | None, hooks, gate: tuple[int, int]) -> None:
    """Fork a go-between that forks the node, answers the supervisor with its pid and exits; the starter
    goes on with the next request meanwhile (go-betweens are reaped by the kernel: SIGCHLD is ignored)."""
    for stream in (sys.stdout, sys.stderr):
        stream.flush()
    if hooks is not None:
        hooks.before()
    try:
        go_between = os.fork()
    except OSError as exc:
        go_between, error = None, exc
    if go_between == 0:
        go_between_forks_node(channel, request, output, hooks, gate)
    if hooks is not None:
        hooks.after_parent()
    if go_between is None:
        channel.sendall(f"error {request.number} cannot fork: {error}".encode(errors="replace"))


def go_between_forks_node(channel: socket.socket, request: NodeRequest, output: int | None, hooks, gate) -> None:
    """In the go-between: fork the node, tell the supervisor its pid, exit (the node is reparented to it)."""
    try:
        os.close(gate[1])
        starter = os.getppid()
        pid = os.fork()
        if pid == 0:
            channel.close()
            if hooks is not None:
                hooks.after_child()
            become_node(request, sys.executable, output, gate[0], starter)
        answer = f"pid {request.number} {pid}"
    except BaseException as exc:  # noqa: BLE001 (a forked child ends in os._exit)
        answer = f"error {request.number} cannot fork: {exc}"
    try:
        channel.sendall(answer.encode(errors="replace"))
    finally:
        os._exit(0)


def serve(channel: socket.socket) -> int:
    """Fork a node per request. The nodes asked for together wait behind a gate (a pipe) until all are forked:
    started at once, 32 nodes would take the processor from the starter and make the last wait seconds."""
    hooks = lttng_fork_hooks()
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)
    channel.sendall(b"ready")
    requests = select.poll()
    requests.register(channel.fileno(), select.POLLIN)
    gate = None
    while True:
        if gate is not None and not requests.poll(0):  # the last request of those asked for at once
            for end in gate:
                os.close(end)  # the gate opens: its last write end is closed
            gate = None
        message, output = receive(channel)
        if not message:
            return 0
        try:
            request = NodeRequest(message)
        except ValueError as exc:
            channel.sendall(f"invalid request: {exc}".encode())  # the supervisor gives up on the starter
        else:
            gate = gate or os.pipe()
            start_node(channel, request, output, hooks, gate)
        if output is not None:
            os.close(output)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="joshua-node-starter", description=__doc__.splitlines()[0])
    parser.add_argument("--socket-fd", type=int, required=True, help="the supervisor's end of their socket")
    parser.add_argument("node_types", nargs="*", help="the node types to import (empty arguments are room for titles)")
    options = parser.parse_args(argv)
    channel = socket.socket(fileno=options.socket_fd)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # it ends when the supervisor closes its socket; nodes set their own
    preload([node_type for node_type in options.node_types if node_type])
    try:
        code = serve(channel)
    except (BrokenPipeError, ConnectionResetError, KeyboardInterrupt):
        code = 0
    end_process(code)  # without the native libraries' teardown, which a process that made no node does not need
    return code
