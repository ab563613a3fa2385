"""The dashboard's HTTP routes (Starlette): the page, the robot's status, the SSE stream and the control actions.

Routes (all under /api/ answer 401 without the owner's bearer token; any route answers 403 to a Host
header outside the allow-list, see security.py):
- `GET /`: the page (web/dist, built by set-up); `GET /api/robot`: topology, streams, recorders, inference nodes;
- `GET /api/status`: the supervisor's status (the JSON of `ctl status --json`); 503 when unreachable;
- `GET /api/events`: Server-Sent Events `status`, `rates`, `joints`, `image`, `scan`, `recorder`, `inference`;
- `GET /api/nodes/<name>/logs?lines=N`: the last lines of a node's log;
- `POST /api/nodes/<name>/restart|stop|start`: a supervisor action; the reply is the supervisor's;
- `POST /api/recorders/<node>/episode/start|stop|discard` (start takes `{"task": TEXT}`): recorder episodes.
No GET changes anything.
"""

import asyncio
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

from joshua_runtime.dashboard.control_client import NODE_ACTIONS, ControlError
from joshua_runtime.dashboard.security import ApiGuard, HostAllowList, HostGuard

STATUS_POLL_S = 1.0
SSE_KEEPALIVE_S = 15.0
DEFAULT_LOG_LINES = 100
MAX_LOG_LINES = 2000
EPISODE_ACTIONS = ("start", "stop", "discard")
MAX_TASK_CHARS = 500


class Dashboard:
    """Holds the robot's parts (view, control client, telemetry, broadcaster) and serves them."""

    def __init__(self, view, control, broadcaster, telemetry, web_dir: Path, token: str, allowed: HostAllowList):
        self.view = view
        self.control = control
        self.broadcaster = broadcaster
        self.telemetry = telemetry
        self.web_dir = web_dir
        self.last_status: dict = {"error": "no status yet"}
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
                self.poller = asyncio.create_task(dashboard._poll_status())

            async def __aexit__(self, *exc_info):
                self.poller.cancel()

        return Lifespan()

    async def _poll_status(self) -> None:
        while True:
            try:
                self.last_status = await self.control.status()
            except ControlError as exc:
                self.last_status = {"error": str(exc)}
            self.broadcaster.publish("status", "status", self.last_status)
            await asyncio.sleep(STATUS_POLL_S)

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
            return JSONResponse({"error": str(exc)}, status_code=503)

    async def events(self, request):
        mailbox = self.broadcaster.subscribe()

        async def stream():
            try:
                yield b"retry: 1000\n\n"
                while True:
                    try:
                        event = await asyncio.wait_for(mailbox.get(), SSE_KEEPALIVE_S)
                    except TimeoutError:
                        yield b": keepalive\n\n"
                        continue
                    yield event.sse()
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
            return JSONResponse({"error": str(exc)}, status_code=502)

    async def node_action(self, request):
        action = request.path_params["action"]
        if action not in NODE_ACTIONS:
            return JSONResponse(
                {"error": f"unknown action {action!r} (use {', '.join(NODE_ACTIONS)})"}, status_code=404
            )
        try:
            reply = await self.control.node_action(action, request.path_params["name"])
        except ControlError as exc:
            return JSONResponse({"error": str(exc)}, status_code=502)
        return JSONResponse(reply)

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
