"""The dashboard's client of its host's agent: the control client's calls, for every host of the robot.

`status()` is the status of every host (each node with its host, see roster.py); a node's restart, stop,
start and log go to the host that runs it, which the manifest says.
"""

import json
import os
from pathlib import Path

from joshua_core import control_plane
from joshua_runtime.dashboard.control_client import BAD_REQUEST, NODE_ACTIONS, NOT_FOUND, ControlClient, ControlError
from joshua_runtime.errors import SettingsError


class HostsControlClient:
    """Sends the dashboard's requests to the agent's socket at `path`; `placement` maps process -> host."""

    def __init__(self, path, placement: dict[str, str]):
        self.agent = ControlClient(path)
        self.placement = placement

    @property
    def path(self):
        return self.agent.path

    def _host(self, node: str) -> str:
        host = self.placement.get(node)
        if host is None:
            raise ControlError(f"no process named {node!r:.80} on any host", NOT_FOUND)
        return host

    async def status(self) -> dict:
        return await self.agent.request({"command": "status", "all_hosts": True})

    async def node_action(self, action: str, node: str) -> dict:
        if action not in NODE_ACTIONS:
            raise ControlError(f"unknown action {action!r} (use {', '.join(NODE_ACTIONS)})", BAD_REQUEST)
        return await self.agent.request({"command": action, "node": node, "host": self._host(node)})

    async def logs(self, node: str, lines: int) -> list[str]:
        request = {"command": "logs", "node": node, "lines": lines, "follow": False, "host": self._host(node)}
        reply = await self.agent.request(request)
        return list(reply.get("lines") or [])


def control_client(manifest: Path, control_socket: Path):
    """The dashboard's client: of its supervisor's control socket, or on a host of a robot on several, of that
    host's agent ($JOSHUA_HOSTS_SOCKET, set by the supervisor; else beside the control socket)."""
    try:
        data = json.loads(manifest.read_text())
    except (OSError, ValueError) as exc:
        raise SettingsError(f"cannot read {manifest}: {exc}") from exc
    if not data.get("hosts"):
        return ControlClient(control_socket)
    path = os.environ.get(control_plane.HOSTS_SOCKET_VARIABLE) or control_plane.hosts_socket_path(str(control_socket))
    placement = {process: host["name"] for host in data["hosts"] for process in host["processes"]}
    return HostsControlClient(Path(path), placement)
