"""The dashboard's HTTP routes (Starlette): the page, the robot's status, the SSE stream and the control actions.

Routes (all under /api/ answer 401 without the owner's bearer token; any route answers 403 to a Host
header outside the allow-list, see security.py):
- `GET /`: the page (web/dist, built by set-up); `GET /api/robot`: topology, streams, processes, recorders, inference nodes;
- `GET /api/status`: the supervisor's status (the JSON of `ctl status --json`); 503 when unreachable;
- `GET /api/events`: Server-Sent Events `status`, `actions`, `rates`, `joints`, `image`, `scan`, `recorder`,
  `inference`, each with the server's `server_time_s`, and `clock` (the server's time, every CLOCK_PERIOD_S);
- `GET /api/nodes/<name>/logs?lines=N`: the last lines of a node's log;
- `POST /api/nodes/<name>/restart|stop|start`: a supervisor action; the reply is the supervisor's, but 202
  for a restart or stop of this dashboard's own process (it stops before the supervisor can answer), and
  202 with the node's state when the supervisor has not answered in time while the node still stops or starts;
- `POST /api/recorders/<node>/episode/start|stop|discard|next|rerecord` (start takes `{"task": TEXT}`):
  recorder episodes (ai/episode_protocol.py).
No GET changes anything. A refusal or failure of the supervisor answers `{"error": LINE, "kind": KIND}`
with the status of CONTROL_ERROR_STATUS. Every reply and event has its shape in api.schema.json.
"""

import asyncio
import json
import os
import time
from pathlib import Path

from starlette.applications import Starlette
from starlette.responses import (
    FileResponse,
    JSONResponse,
    PlainTextResponse,
    StreamingResponse,
)
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from joshua_runtime.ai import episode_protocol
from joshua_runtime.dashboard import control_client as control
from joshua_runtime.dashboard.api_schema import event_kind
from joshua_runtime.dashboard.control_client import NODE_ACTIONS, ControlError
from joshua_runtime.dashboard.security import ApiGuard, HostAllowList, HostGuard

STATUS_POLL_S = 1.0
# At the start, and after an action asked through this dashboard, the supervisor is asked this often until
# every node has settled (running and ready, or stopped), for at most QUICK_POLL_WINDOW_S: the page shows
# a restart, a stop and a node's readiness as they happen, not up to STATUS_POLL_S later.
QUICK_POLL_S = 0.1
QUICK_POLL_WINDOW_S = 10.0
# The stream sends the server's clock this often (the page measures the age of what it shows against it);
# it also keeps an idle stream open.
CLOCK_PERIOD_S = 1.0
# The HTTP status of each kind of ControlError.
CONTROL_ERROR_STATUS = {
    control.CONFLICT: 409,
    control.REFUSED: 409,
    control.NOT_FOUND: 404,
    control.BAD_REQUEST: 400,
    control.INVALID_BUILD: 422,
    control.PREFLIGHT: 422,
    control.FORBIDDEN: 403,
    control.BUSY: 503,
    control.STOPPING: 503,
    control.UNREACHABLE: 503,
    control.TIMEOUT: 504,
    control.BROKEN: 502,
}
DEFAULT_LOG_LINES = 100
MAX_LOG_LINES = 2000
EPISODE_ACTIONS = episode_protocol.COMMANDS  # the schema's EpisodeAction (tests/test_dashboard_api.py)
MAX_TASK_CHARS = 500
STATUS_EVENT = event_kind("status")
ACTIONS_EVENT = event_kind("actions")
CLOCK_EVENT = event_kind("clock")


class Dashboard:
    """Holds the robot's parts (view, control client, telemetry, broadcaster) and serves them."""

    def __init__(self, view, control, broadcaster, telemetry, web_dir: Path, token: str, allowed: HostAllowList):
        self.view = view
        self.control = control
        self.broadcaster = broadcaster
        self.telemetry = telemetry
        self.web_dir = web_dir
        self.last_status: dict = {"error": "no status yet"}
        self.pending: dict[str, str] = {}  # node -> the action asked through this dashboard and not answered yet
        self.stopping = asyncio.Event()  # set once this server was asked to stop (note_stopping)
        self.poll_now = asyncio.Event()  # the status poller asks the supervisor at once (poll_quickly)
        self.quick_until = 0.0  # the poller polls every QUICK_POLL_S until then (event loop's time)
        routes = [
            Route("/", self.page),
            Route("/api/robot", self.robot),
            Route("/api/status", self.status),
            Route("/api/events", self.events),
            Route("/api/nodes/{name}/logs", self.logs),
            Route("/api/nodes/{name}/{action}", self.node_action, methods=["POST"]),
            Route("/api/recorders/{node}/episode/{action}", self.episode_action, methods=["POST"]),
        ]
        if (web_dir / "assets").is_dir():
            routes.append(Mount("/assets", StaticFiles(directory=web_dir / "assets")))
        self.app = Starlette(routes=routes, lifespan=self._lifespan)
        self.app.add_middleware(ApiGuard, token=token)
        self.app.add_middleware(HostGuard, allowed=allowed)  # added last: it runs first

    def _lifespan(self, _app):
        dashboard = self

        class Lifespan:
            async def __aenter__(self):
                dashboard.broadcaster.attach(asyncio.get_running_loop())
                # Replayed to every page that connects: none of this server's actions is under way (a
                # page that saw a restart of the dashboard itself under way learns that it ended).
                dashboard.broadcaster.publish(ACTIONS_EVENT, ACTIONS_EVENT, {"pending": {}})
                self.poller = asyncio.create_task(dashboard._poll_status())

            async def __aexit__(self, *exc_info):
                self.poller.cancel()

        return Lifespan()

    def note_stopping(self) -> None:
        """This server is about to stop (called from the event loop's thread): requests waiting for the
        supervisor get their answer now rather than be cut by the shutdown, and event streams end."""
        self.stopping.set()
        self.broadcaster.wake_all()

    def poll_quickly(self) -> None:
        """Ask the supervisor for its status now, then every QUICK_POLL_S until every node has settled (called
        from the event loop's thread)."""
        self.quick_until = asyncio.get_running_loop().time() + QUICK_POLL_WINDOW_S
        self.poll_now.set()

    async def _poll_status(self) -> None:
        loop = asyncio.get_running_loop()
        self.poll_quickly()  # the nodes start with this server, or restart
        while True:
            self.poll_now.clear()
            try:
                self.last_status = await self.control.status()
            except ControlError as exc:
                self.last_status = {"error": str(exc), "kind": exc.kind}
            self.broadcaster.publish(STATUS_EVENT, STATUS_EVENT, self.last_status)
            quick = loop.time() < self.quick_until and not _settled(self.last_status)
            try:
                await asyncio.wait_for(self.poll_now.wait(), QUICK_POLL_S if quick else STATUS_POLL_S)
            except asyncio.TimeoutError:
                pass

    async def page(self, _request):
        index = self.web_dir / "index.html"
        if not index.is_file():
            return PlainTextResponse(f"the page is not built ({index} is missing): run `make setup`", status_code=503)
        return FileResponse(index)

    async def robot(self, _request):
        return JSONResponse(self.view.summary())

    async def status(self, _request):
        try:
            return JSONResponse(await self.control.status())
        except ControlError as exc:
            return _control_error(exc, unavailable=True)

    async def events(self, request):
        mailbox = self.broadcaster.subscribe()
        loop = asyncio.get_running_loop()

        async def stream():
            # The stream ends once the server is asked to stop (note_stopping wakes its wait): it would hold the
            # shutdown for its grace. It waits for events across clock ticks and sends those that came meanwhile
            # in one write; a client that goes away ends it as it waits (Starlette cancels the stream).
            try:
                yield b"retry: 1000\n\n"
                yield _clock_event()
                next_clock = loop.time() + CLOCK_PERIOD_S
                while not self.stopping.is_set():
                    await mailbox.wait(max(0.0, next_clock - loop.time()))
                    if self.stopping.is_set():
                        return
                    chunk = b"".join(event.sse for event in mailbox.take_all())
                    if loop.time() >= next_clock:
                        chunk = _clock_event() + chunk
                        next_clock = loop.time() + CLOCK_PERIOD_S
                    if chunk:
                        yield chunk
            finally:
                self.broadcaster.unsubscribe(mailbox)

        return StreamingResponse(
            stream(), media_type="text/event-stream", headers={"Cache-Control": "no-store", "X-Accel-Buffering": "no"}
        )

    async def logs(self, request):
        try:
            lines = min(MAX_LOG_LINES, max(1, int(request.query_params.get("lines", DEFAULT_LOG_LINES))))
        except ValueError:
            return JSONResponse({"error": "lines must be a whole number"}, status_code=400)
        try:
            return JSONResponse({"lines": await self.control.logs(request.path_params["name"], lines)})
        except ControlError as exc:
            return _control_error(exc)

    async def node_action(self, request):
        action = request.path_params["action"]
        if action not in NODE_ACTIONS:
            return JSONResponse(
                {"error": f"unknown action {action!r} (use {', '.join(NODE_ACTIONS)})"}, status_code=404
            )
        node = request.path_params["name"]
        first = node not in self.pending  # a second action meanwhile is the supervisor's to refuse
        if first:
            self._note_pending(node, action)
        try:
            reply = await self._unless_stopping(self.control.node_action(action, node))
        except ControlError as exc:
            # No answer in time: from the supervisor (TIMEOUT), or from another host's agent (UNREACHABLE).
            under_way = exc.kind in (control.TIMEOUT, control.UNREACHABLE) and await self._action_under_way(node)
            return JSONResponse(under_way, status_code=202) if under_way else _control_error(exc)
        finally:
            if first:
                self._note_pending(node, None)
            self.poll_quickly()
        if reply is not None:
            return JSONResponse(reply)
        if node == self.view.dashboard_process:  # stopping as asked: the supervisor carries on without us
            return JSONResponse({"node": node, "state": "stopping", "pid": os.getpid()}, status_code=202)
        return JSONResponse({"error": "the dashboard is stopping", "kind": control.STOPPING}, status_code=503)

    async def _action_under_way(self, node: str) -> dict | None:
        """The node's entry (name, state, pid) when it is still stopping or starting: the supervisor answers an
        action once it is done, and a node may take longer to stop than a request waits (it can ask for more
        time, see supervisor/notify.py); None when it is not, or the supervisor does not answer either."""
        try:
            status = await self.control.status()
        except ControlError:
            return None
        entry = next((item for item in status.get("nodes", ()) if item.get("name") == node), None)
        if entry is None or _node_settled(entry):
            return None
        return {"node": node, "state": entry["state"], "pid": entry.get("pid")}

    async def _unless_stopping(self, request) -> dict | None:
        """The supervisor's answer to `request`, or None when this server began to stop first (the
        request reached the supervisor, which carries it out)."""
        answer = asyncio.ensure_future(request)
        stopping = asyncio.ensure_future(self.stopping.wait())
        try:
            await asyncio.wait({answer, stopping}, return_when=asyncio.FIRST_COMPLETED)
        finally:
            stopping.cancel()
        if answer.done():
            return answer.result()
        answer.cancel()
        return None

    def _note_pending(self, node: str, action: str | None) -> None:
        """Note an action asked through this dashboard (None: it was answered) and tell every page."""
        if action is None:
            self.pending.pop(node, None)
        else:
            self.pending[node] = action
        self.broadcaster.publish(ACTIONS_EVENT, ACTIONS_EVENT, {"pending": dict(self.pending)})

    async def episode_action(self, request):
        node, action = request.path_params["node"], request.path_params["action"]
        if node not in {r.node for r in self.view.recorders}:
            return JSONResponse({"error": f"no recorder node named {node!r}"}, status_code=404)
        if action not in EPISODE_ACTIONS:
            return JSONResponse(
                {"error": f"unknown episode action {action!r} (use {', '.join(EPISODE_ACTIONS)})"}, status_code=404
            )
        command = action
        if action == "start":
            task = await _task_text(request)
            if task is None:
                return JSONResponse(
                    {
                        "error": f'the body must be JSON {{"task": TEXT}} of at most {MAX_TASK_CHARS} '
                        "characters on one line"
                    },
                    status_code=400,
                )
            command = f"start {task}".strip()
        self.telemetry.send_episode_command(node, command)
        return JSONResponse({"node": node, "command": command})


def _control_error(exc: ControlError, unavailable: bool = False) -> JSONResponse:
    """The reply to a refusal or failure of the supervisor; `unavailable`: a refusal of a status request
    means no status is available (503)."""
    status = CONTROL_ERROR_STATUS.get(exc.kind, 502)
    if unavailable and status != 502:
        status = 503
    return JSONResponse({"error": str(exc), "kind": exc.kind}, status_code=status)


def _settled(status: dict) -> bool:
    """Every node of a supervisor's status is running and ready, or stopped (False without a status)."""
    nodes = status.get("nodes")
    return nodes is not None and all(_node_settled(node) for node in nodes)


def _node_settled(node: dict) -> bool:
    """One node of a supervisor's status is running and ready, or stopped: no action on it is under way."""
    return node["state"] == "stopped" or (node["state"] == "running" and node["ready"])


def _clock_event() -> bytes:
    return f"event: {CLOCK_EVENT}\ndata: {json.dumps({'server_time_s': round(time.time(), 3)})}\n\n".encode()


async def _task_text(request) -> str | None:
    """The task text of a start request (empty when no body), or None when the body is malformed."""
    body = await request.body()
    if not body.strip():
        return ""
    try:
        task = (await request.json()).get("task", "")
    except (ValueError, AttributeError):
        return None
    if not isinstance(task, str) or len(task) > MAX_TASK_CHARS or "\n" in task:
        return None
    return task.strip()
