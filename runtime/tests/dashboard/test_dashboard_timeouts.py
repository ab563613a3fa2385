"""The dashboard's own timeouts end where it means them to, and its event stream ends cleanly, on every Python
the runtime supports.

asyncio.wait_for's timeout is asyncio.TimeoutError, which only Python 3.11 made the builtin TimeoutError: a
supervisor that never answers must still be a ControlError of kind timeout, and the event stream's clock must
keep ticking when nothing else happens (runtime/tests/interpreters/ runs this module on 3.10 and 3.12).
"""

import asyncio
import socket
from pathlib import Path

import pytest

from joshua_runtime.dashboard import app, control_client
from joshua_runtime.dashboard.app import Dashboard
from joshua_runtime.dashboard.broadcaster import Broadcaster
from joshua_runtime.dashboard.robot_view import load_robot_view
from joshua_runtime.dashboard.security import HostAllowList

MOCK_ARM = Path(__file__).resolve().parents[3] / "generated" / "mock_arm" / "manifest.json"
SHORT_TIMEOUT_S = 0.3  # the request timeout and clock period here, instead of seconds
CLOCKS = 3  # clock events read from the stream: the first comes at once, the others each after a timeout
TEST_TIMEOUT_S = 30


@pytest.mark.timeout(TEST_TIMEOUT_S)
def test_a_supervisor_that_never_answers_is_a_timeout_error(tmp_path, monkeypatch):
    path = tmp_path / "silent.sock"
    listener = socket.socket(socket.AF_UNIX)
    listener.bind(str(path))
    listener.listen()  # connections complete in the backlog; nothing ever reads or answers them
    monkeypatch.setattr(control_client, "REQUEST_TIMEOUT_S", SHORT_TIMEOUT_S)
    try:
        with pytest.raises(control_client.ControlError) as raised:
            asyncio.run(control_client.ControlClient(path).request({"command": "status"}))
    finally:
        listener.close()
    assert raised.value.kind == control_client.TIMEOUT
    assert str(raised.value) == f"the supervisor did not answer 'status' within {SHORT_TIMEOUT_S:g} s"


def dashboard_of(control, tmp_path) -> Dashboard:
    return Dashboard(
        load_robot_view(MOCK_ARM),
        control,
        Broadcaster(),
        telemetry=None,
        web_dir=tmp_path / "no-page",
        token="owner-token",
        allowed=HostAllowList("127.0.0.1"),
    )


@pytest.mark.timeout(TEST_TIMEOUT_S)
def test_the_event_stream_keeps_its_clock_with_nothing_else_to_send(tmp_path, monkeypatch):
    monkeypatch.setattr(app, "CLOCK_PERIOD_S", SHORT_TIMEOUT_S)
    dashboard = dashboard_of(control_client.ControlClient(tmp_path / "no.sock"), tmp_path)

    async def clock_events() -> list[bytes]:
        response = await dashboard.events(None)
        chunks = []
        async for chunk in response.body_iterator:
            if chunk.startswith(b"event: clock"):
                chunks.append(chunk)
            if len(chunks) == CLOCKS:
                break
        await response.body_iterator.aclose()
        return chunks

    assert len(asyncio.run(clock_events())) == CLOCKS


@pytest.mark.timeout(TEST_TIMEOUT_S)
def test_the_event_stream_ends_as_soon_as_the_server_is_asked_to_stop(tmp_path, monkeypatch):
    monkeypatch.setattr(app, "CLOCK_PERIOD_S", TEST_TIMEOUT_S)  # nothing else would end the wait
    dashboard = dashboard_of(control_client.ControlClient(tmp_path / "no.sock"), tmp_path)

    async def read_until_stopped() -> list[bytes]:
        response = await dashboard.events(None)
        chunks = [await anext(response.body_iterator) for _ in range(2)]  # the retry, the first clock
        asyncio.get_running_loop().call_later(SHORT_TIMEOUT_S, dashboard.note_stopping)
        return chunks + [chunk async for chunk in response.body_iterator]

    chunks = asyncio.run(asyncio.wait_for(read_until_stopped(), 10 * SHORT_TIMEOUT_S))
    assert chunks[1].startswith(b"event: clock") and len(chunks) == 2


@pytest.mark.timeout(TEST_TIMEOUT_S)
def test_a_client_that_goes_away_leaves_no_task_of_its_stream_behind(tmp_path, monkeypatch):
    """A browser that closes its page cancels the stream as it waits for the next event (Starlette cancels it)."""
    monkeypatch.setattr(app, "CLOCK_PERIOD_S", TEST_TIMEOUT_S)  # the stream waits for an event meanwhile
    dashboard = dashboard_of(control_client.ControlClient(tmp_path / "no.sock"), tmp_path)

    async def tasks_left_after_a_disconnection() -> list[asyncio.Task]:
        response = await dashboard.events(None)

        async def read_all() -> None:
            async for _chunk in response.body_iterator:
                pass

        reader = asyncio.ensure_future(read_all())
        await asyncio.sleep(SHORT_TIMEOUT_S)  # the retry and the first clock are read; it waits for more
        reader.cancel()
        await asyncio.gather(reader, return_exceptions=True)
        await asyncio.sleep(0)  # what the stream cancelled as it ended finishes cancelling
        return [task for task in asyncio.all_tasks() if task is not asyncio.current_task()]

    assert asyncio.run(tasks_left_after_a_disconnection()) == []
    assert dashboard.broadcaster.mailboxes == set()


class SettlingSupervisor:
    """A supervisor whose one node is ready from its `ready_from`th status on; counts the status requests."""

    def __init__(self, ready_from: int):
        self.ready_from = ready_from
        self.requests = 0

    async def status(self) -> dict:
        self.requests += 1
        ready = self.requests >= self.ready_from
        return {"nodes": [{"name": "lidar", "state": "running", "pid": 7, "restarts": 0, "ready": ready}]}


@pytest.mark.timeout(TEST_TIMEOUT_S)
def test_the_status_is_polled_quickly_until_every_node_is_ready_and_at_once_after_an_action(tmp_path, monkeypatch):
    monkeypatch.setattr(app, "STATUS_POLL_S", TEST_TIMEOUT_S)  # a slow poll would not come during the test
    supervisor = SettlingSupervisor(ready_from=3)
    dashboard = dashboard_of(supervisor, tmp_path)

    async def requests_over_time() -> list[int]:
        poller = asyncio.create_task(dashboard._poll_status())
        counts = []
        for _ in range(2):
            await asyncio.sleep(10 * app.QUICK_POLL_S)
            counts.append(supervisor.requests)
        dashboard.poll_quickly()
        await asyncio.sleep(app.QUICK_POLL_S)
        counts.append(supervisor.requests)
        poller.cancel()
        return counts

    # Three requests until the node is ready (the third says so), none more while it stays so; one more at once
    # after an action.
    assert asyncio.run(requests_over_time()) == [3, 3, 4]
