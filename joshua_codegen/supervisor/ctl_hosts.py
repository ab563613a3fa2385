"""`ctl --host NAME ...` and `ctl status --all-hosts`: other hosts of a robot on several, through this host's agent."""

from joshua_codegen.supervisor.robot import ROBOT

HOSTS_SOCKET_VARIABLE = "JOSHUA_HOSTS_SOCKET"  # told to every node, so the host's agent and dashboard find it
SOCKET_SUFFIX = ".sock"
HOSTS_SOCKET_SUFFIX = ".hosts.sock"
UNREACHABLE_KIND = "unreachable"
WAIT_FIELD = "wait_s"  # how long the sender of a request waits for its answer (joshua_runtime/hosts/requests.py)


def hosts_socket_path(control_socket: str) -> str:
    """The agent's socket beside `control_socket`: `split.arm.hosts.sock` for `split.arm.sock`.

    The agent (`host_agent_<host>`, joshua_runtime/hosts) serves it, owned and checked like the control socket.
    It takes the control socket's requests with one more field: "host" (the host whose supervisor answers, over
    the robot's authenticated Zenoh when it is another) or "all_hosts" (the status of every host at once, each
    node with its host), and may say how long its sender waits for the answer ("wait_s", which `ctl` sends with
    a stop, a restart or a reload: the agents on the way wait as long, less a margin at each hop). Its refusals
    add the kind "unreachable": the host has not been heard from, or did not answer in time.
    """
    return control_socket.removesuffix(SOCKET_SUFFIX) + HOSTS_SOCKET_SUFFIX


def hosts_usage_problem(options) -> str | None:
    """Why `--host` / `--all-hosts` cannot be used as given, or None."""
    if not (options.host or getattr(options, "all_hosts", False)):
        return None
    if not ROBOT.get("host"):
        return f"robot {ROBOT['name']} runs on one computer: --host and --all-hosts are for a robot on several"
    if options.host and options.host not in ROBOT["hosts"]:
        return f"robot {ROBOT['name']} has no host {options.host!r} (hosts: {', '.join(ROBOT['hosts'])})"
    if options.command == "reload":
        return "reload applies a build on the host it runs on: run it there, without --host"
    if options.command == "logs" and options.follow:
        return "logs -f follows a node of this host only: run it on that host"
    return None


def print_all_hosts(reply: dict) -> None:
    """Every host's line (reachable or not, its Discovery Server), then every node with its host."""
    for host in reply["hosts"]:
        heard = "reachable" if host["reachable"] else f"unreachable ({host['detail']})"
        discovery = host.get("discovery") or {}
        server = ""
        if discovery:
            known = {True: "reachable", False: "unreachable", None: "unknown"}[discovery["reachable"]]
            server = f", discovery server {discovery['server']} {known}"
        print(f"host {host['name']:18} {heard}{server}")
    for node in reply["nodes"]:
        pid = f"pid {node['pid']}" if node["pid"] else "no process"
        since = f"{node['since_s']:.0f} s" if node["since_s"] is not None else "-"
        waiting = f", waiting for {', '.join(node['waiting_for'])}" if node.get("waiting_for") else ""
        print(
            f"{node['host']:12} {node['name']:24} {node['state']:9} {pid:12} {node['restarts']} restarts, {since}{waiting}"
        )
