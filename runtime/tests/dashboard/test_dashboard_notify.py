"""The dashboard tells its process manager it is ready, and pings the watchdog only when one is asked for."""

import asyncio
from types import SimpleNamespace

import pytest

from joshua_runtime.dashboard.cli import notify_manager
from joshua_runtime.notify import Notifier

TEST_TIMEOUT_S = 30
PINGS = 3
WATCHDOG_S = 0.2


class RecordingNotifier(Notifier):
    """A notifier that notes what it would send instead of sending it."""

    def __init__(self, watchdog_interval_s: float | None):
        super().__init__("@unused", watchdog_interval_s)
        self.sent: list[tuple[str, ...]] = []
        self.pinged = asyncio.Event()

    def send(self, *assignments: str) -> bool:
        self.sent.append(assignments)
        if sum(1 for lines in self.sent if lines == ("WATCHDOG=1",)) >= PINGS:
            self.pinged.set()
        return True


@pytest.mark.timeout(TEST_TIMEOUT_S)
def test_without_a_watchdog_the_notifier_ends_once_ready():
    async def run() -> list[tuple[str, ...]]:
        notifier = RecordingNotifier(None)
        await notify_manager(SimpleNamespace(started=True), notifier, "http://127.0.0.1:8640/")
        return notifier.sent

    assert asyncio.run(run()) == [("READY=1", "STATUS=serving http://127.0.0.1:8640/")]


@pytest.mark.timeout(TEST_TIMEOUT_S)
def test_with_a_watchdog_the_notifier_pings_it_while_the_loop_runs():
    async def run() -> list[tuple[str, ...]]:
        notifier = RecordingNotifier(WATCHDOG_S)
        task = asyncio.create_task(notify_manager(SimpleNamespace(started=True), notifier, "http://x/"))
        await notifier.pinged.wait()
        task.cancel()
        return notifier.sent

    sent = asyncio.run(run())
    assert sent[0][0] == "READY=1" and sent[1 : PINGS + 1] == [("WATCHDOG=1",)] * PINGS
