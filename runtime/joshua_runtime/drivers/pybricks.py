"""Driver of a Pybricks hub running the two-motor hub program (pybricks_hub_program.py), ROS-free.

`open()` connects through a HubTransport, downloads and starts the hub program unless it already
runs, and waits for its first angle report. Commands then go to the program's stdin as framed lines
(pybricks_protocol.py); its angle reports arrive on stdout and `latest` holds the newest one. The
BLE work runs on an asyncio loop in a thread of its own, so a ROS node calls plain methods.

The link counts as lost when the transport reports a disconnection or when no angle report came
for DEVICE_SILENCE_S (a frozen controller or hub says nothing at all). From then on `link_lost_at`
and `lost_reason` say so, commands are dropped (the hub program stops the wheels when it hears
nothing for HUB_WATCHDOG_MS), and the driver reconnects from scratch (the transport released, the
controller opened again) with a back-off from RECONNECT_FIRST_DELAY_S to RECONNECT_MAX_DELAY_S, each
attempt bounded by RECONNECT_ATTEMPT_TIMEOUT_S, until it succeeds or `close()`; after a reconnection
it stops the wheels. How long to keep trying is the caller's choice (HUB_RECONNECT_WINDOW_S for the
base node). Every wait is bounded, so `close()` returns within CLOSE_TIMEOUT_S + CANCEL_TIMEOUT_S.
"""

import asyncio
import struct
import threading
import time
from concurrent.futures import Future
from concurrent.futures import TimeoutError as FutureTimeoutError

from joshua_core.device_link import DEVICE_SILENCE_S
from joshua_runtime.drivers.driver import Driver
from joshua_runtime.drivers.pybricks_protocol import (
    CMD_START_PROGRAM,
    CMD_STOP_PROGRAM,
    CMD_WRITE_PROGRAM_META,
    CMD_WRITE_RAM,
    CMD_WRITE_STDIN,
    EVENT_STATUS,
    EVENT_STDOUT,
    STATUS_PROGRAM_RUNNING,
    WRITE_RAM_HEADER,
    AngleReport,
    LineAssembler,
    encode_line,
    parse_angles,
    status_flags,
    unpack_capabilities,
)
from joshua_runtime.drivers.pybricks_transport import HubTransport
from joshua_runtime.errors import DeviceError

CONNECT_TIMEOUT_S = 15.0
STATUS_WAIT_S = 0.3
START_TIMEOUT_S = 3.0
FIRST_REPORT_TIMEOUT_S = 2.0
# How often the telemetry watchdog looks at the age of the newest angle report.
TELEMETRY_POLL_S = 0.1
# Reconnection: the first attempt this long after the loss, each next one twice as long after, at most
# RECONNECT_MAX_DELAY_S apart; one attempt (controller, scan, connection, program) may take this long.
RECONNECT_FIRST_DELAY_S = 0.25
RECONNECT_MAX_DELAY_S = 1.0
RECONNECT_ATTEMPT_TIMEOUT_S = 5.0
# How long releasing a dead link may take before the driver goes on without it.
RELEASE_TIMEOUT_S = 1.0
# A base node gives up (exit code 3, restarted by its supervisor) when the link is not back this long after its loss.
HUB_RECONNECT_WINDOW_S = 10.0
ACK_TIMEOUT_S = 1.0
CLOSE_TIMEOUT_S = 2.0
# After a timed-out wait, how long its cancelled work may take to end.
CANCEL_TIMEOUT_S = 0.5


class PybricksHub(Driver):
    """One hub running the motor program; speeds in deg/s, angles in degrees (left, right)."""

    def __init__(self, hub: str, transport: HubTransport, program: bytes):
        self.hub, self.transport, self.program = hub, transport, program
        self.latest: AngleReport | None = None
        self.connected = False
        self.reconnects = 0
        self.link_losses = 0
        self.link_lost_at: float | None = None  # time.monotonic() of the loss; None while the link is up
        self.lost_reason = ""
        self.last_attempt_error = ""  # why the newest reconnection attempt failed
        self.last_outage_s = 0.0  # how long the link was down before the newest reconnection
        self.lines = LineAssembler()
        self._seq = 0
        self._acks: dict[int, asyncio.Future] = {}
        self._status: int | None = None
        self._status_changed: asyncio.Event | None = None
        self._reported: asyncio.Event | None = None
        self._last_report_at = 0.0
        self._link = 0  # which connection the transport's disconnection callbacks belong to
        self._opened = False
        self._closing = False
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, name="pybricks-ble", daemon=True)

    # --- plain methods, called from any thread --------------------------------------------------

    def open(self) -> None:
        self.run_on_loop(self._setup(), CONNECT_TIMEOUT_S + START_TIMEOUT_S + FIRST_REPORT_TIMEOUT_S)

    def set_speeds(self, left_dps: float, right_dps: float) -> Future:
        """Send both wheel speeds; the future resolves when the hub acknowledged them (None if the link is down)."""
        return asyncio.run_coroutine_threadsafe(self._command("V", float(left_dps), float(right_dps)), self._loop)

    def stop_wheels(self) -> Future:
        return asyncio.run_coroutine_threadsafe(self._command("S"), self._loop)

    def lost_for(self) -> float | None:
        """Seconds since the link was lost; None while it is up."""
        lost_at = self.link_lost_at
        return None if lost_at is None else time.monotonic() - lost_at

    def close(self) -> None:
        """Stop the wheels and the program if the link is up, release the link; never raises, bounded in time."""
        if not self._thread.is_alive():
            return
        try:
            self.run_on_loop(self._shutdown(), CLOSE_TIMEOUT_S)
        except DeviceError:
            pass
        try:
            asyncio.run_coroutine_threadsafe(_cancel_other_tasks(), self._loop).result(CANCEL_TIMEOUT_S)
        except FutureTimeoutError:  # a task that ignores cancellation dies with the daemon thread
            pass
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join(CANCEL_TIMEOUT_S)

    def run_on_loop(self, coroutine, timeout: float):
        """Run a coroutine on the driver's event loop and return its result; DeviceError after `timeout`."""
        if not self._thread.is_alive():
            self._thread.start()
        future = asyncio.run_coroutine_threadsafe(asyncio.wait_for(coroutine, timeout), self._loop)
        try:
            return future.result(timeout + CANCEL_TIMEOUT_S)
        except (asyncio.TimeoutError, FutureTimeoutError):  # the coroutine's wait_for, or this wait
            future.cancel()
            raise DeviceError(f"Pybricks hub {self.hub!r} did not answer within {timeout:g} s") from None

    # --- on the driver's event loop -------------------------------------------------------------

    async def _setup(self) -> None:
        self._status_changed, self._reported = asyncio.Event(), asyncio.Event()
        await self._connect()
        self._opened = True
        self._loop.create_task(self._watch_telemetry())

    async def _connect(self) -> None:
        """Connect, start the program unless it runs, wait for its first angle report; the link is then up."""
        self._link += 1
        link = self._link
        await self.transport.connect(self.hub, self._on_event, lambda reason: self._on_disconnect(link, reason))
        await self._ensure_program()
        self._last_report_at = time.monotonic()
        self.connected = True

    async def _ensure_program(self) -> None:
        """Start the program unless it runs; wait for its first angle report on this connection."""
        self._reported.clear()
        await self._wait_status(STATUS_WAIT_S)
        if not (self._status or 0) & STATUS_PROGRAM_RUNNING:
            await self._download()
            await self.transport.write_command(bytes([CMD_START_PROGRAM]))
            if not await self._wait_running(START_TIMEOUT_S):
                raise DeviceError(f"Pybricks hub {self.hub!r} did not start its program within {START_TIMEOUT_S:g} s")
        try:
            await asyncio.wait_for(self._reported.wait(), FIRST_REPORT_TIMEOUT_S)
        except asyncio.TimeoutError:
            raise DeviceError(
                f"Pybricks hub {self.hub!r} runs a program that sends no wheel angles: is another program on the hub?"
            ) from None

    async def _download(self) -> None:
        caps = unpack_capabilities(await self.transport.read_capabilities())
        if len(self.program) > caps.max_program:
            raise DeviceError(f"hub program is {len(self.program)} bytes, the hub takes {caps.max_program}")
        chunk = caps.max_write - WRITE_RAM_HEADER
        await self.transport.write_command(struct.pack("<BI", CMD_WRITE_PROGRAM_META, 0))
        for offset in range(0, len(self.program), chunk):
            payload = self.program[offset : offset + chunk]
            await self.transport.write_command(struct.pack("<BI", CMD_WRITE_RAM, offset) + payload)
        await self.transport.write_command(struct.pack("<BI", CMD_WRITE_PROGRAM_META, len(self.program)))

    async def _wait_status(self, timeout: float) -> None:
        if self._status is None:
            try:
                await asyncio.wait_for(self._status_changed.wait(), timeout)
            except asyncio.TimeoutError:
                pass

    async def _wait_running(self, timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while not (self._status or 0) & STATUS_PROGRAM_RUNNING:
            self._status_changed.clear()
            try:
                await asyncio.wait_for(self._status_changed.wait(), max(deadline - time.monotonic(), 0))
            except asyncio.TimeoutError:
                return False
        return True

    async def _command(self, *fields) -> float | None:
        """Write one command line; the round-trip time in seconds once acknowledged, None when not sent."""
        if not self.connected:
            return None
        self._seq = self._seq % 9999 + 1
        ack = self._acks[self._seq] = self._loop.create_future()
        sent = time.perf_counter()
        try:
            await self.transport.write_command(
                bytes([CMD_WRITE_STDIN]) + encode_line(fields[0], self._seq, *fields[1:])
            )
            await asyncio.wait_for(ack, ACK_TIMEOUT_S)
            return time.perf_counter() - sent
        except Exception:  # a link that drops mid-command fails the write in transport-specific ways
            return None
        finally:
            self._acks.pop(self._seq, None)

    def _on_event(self, event: bytes) -> None:
        if not event:
            return
        if event[0] == EVENT_STATUS and len(event) >= 5:
            self._status = status_flags(event)
            self._status_changed.set()
        elif event[0] == EVENT_STDOUT:
            for fields in self.lines.feed(event[1:]):
                self._on_line(fields)

    def _on_line(self, fields: list[str]) -> None:
        report = parse_angles(fields)
        if report is not None:
            self.latest = report
            self._last_report_at = time.monotonic()
            self._reported.set()
        elif fields[0] == "K" and len(fields) == 2 and fields[1].isdigit():
            ack = self._acks.get(int(fields[1]))
            if ack is not None and not ack.done():
                ack.set_result(True)

    def _on_disconnect(self, link: int, reason: str) -> None:
        if link == self._link:  # not the late farewell of a connection released already
            self._lose(reason)

    async def _watch_telemetry(self) -> None:
        """Declare the link lost when, counted as up, it brings no angle report for DEVICE_SILENCE_S.

        Also the net under a disconnection that came while a reconnection was finishing.
        """
        while not self._closing:
            await asyncio.sleep(TELEMETRY_POLL_S)
            if self.link_lost_at is None and time.monotonic() - self._last_report_at > DEVICE_SILENCE_S:
                self._lose(f"no wheel angles for {DEVICE_SILENCE_S:g} s")

    def _lose(self, reason: str) -> None:
        """The link is gone: drop what waits on it and start reconnecting (once per loss)."""
        self.connected = False
        self._status = None
        if self._closing or not self._opened or self.link_lost_at is not None:
            return
        self.link_lost_at, self.lost_reason = time.monotonic(), reason
        self.link_losses += 1
        for ack in self._acks.values():
            if not ack.done():
                ack.set_exception(ConnectionError(reason))
        self._loop.create_task(self._reconnect())

    async def _reconnect(self) -> None:
        delay = RECONNECT_FIRST_DELAY_S
        while not self._closing:
            await self._release()
            await asyncio.sleep(delay)
            if self._closing:
                return
            try:
                await asyncio.wait_for(self._connect(), RECONNECT_ATTEMPT_TIMEOUT_S)
            except asyncio.TimeoutError:
                self.last_attempt_error = f"no answer within {RECONNECT_ATTEMPT_TIMEOUT_S:g} s"
            except Exception as exc:  # DeviceError, or how a link dropping mid-attempt fails in a transport
                self.last_attempt_error = str(exc) or type(exc).__name__
            else:
                self.last_outage_s = time.monotonic() - self.link_lost_at
                self.last_attempt_error = ""
                self.reconnects += 1
                self.link_lost_at = None
                await self._command("S")  # whatever the wheels did before the loss, they wait for a new command
                return
            self.connected = False
            delay = min(2 * delay, RECONNECT_MAX_DELAY_S)

    async def _release(self) -> None:
        """Let go of the lost link and its controller, so that the next attempt starts afresh."""
        self._link += 1
        try:
            await asyncio.wait_for(self.transport.reset(), RELEASE_TIMEOUT_S)
        except Exception:  # a dead link fails its release in transport-specific ways; it is dropped all the same
            pass

    async def _shutdown(self) -> None:
        self._closing = True
        if self.connected:
            await self._command("S")
            try:
                await asyncio.wait_for(self.transport.write_command(bytes([CMD_STOP_PROGRAM])), ACK_TIMEOUT_S)
            except Exception:  # the link may be gone already; there is nothing left to stop then
                pass
        self._link += 1
        try:
            await self.transport.close()
        except Exception:  # a dead link fails its release in transport-specific ways; the process lets go of it anyway
            pass


async def _cancel_other_tasks() -> None:
    """End what still runs on the loop (a reconnection attempt, Bumble's timers) before it stops."""
    tasks = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
    for task in tasks:
        task.cancel()
    await asyncio.gather(*tasks, return_exceptions=True)
