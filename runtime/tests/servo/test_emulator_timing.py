"""The STS3215 emulator serves at real-time priority (figures: bench/servo_replies.py) and models a USB
adapter's latency timer; the drivers and tools allow for that latency and for their own thread running late."""

import json
import os
import time

import serial

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers import sts3215_transport
from joshua_runtime.drivers.sts3215_transport import REPLY_TIMEOUT_S, WRITE_TIMEOUT_S, Expected, SerialTransport
from joshua_runtime.servo_tools.bus import open_bus
from joshua_runtime.servo_tools.cli import main
from joshua_runtime.servo_tools.scan import ping_every_id

FTDI_LATENCY_TIMER_S = 0.016  # an FTDI adapter's default: a short reply waits this long in the chip
REPLY_LANDS_S = 0.05  # ample time for the emulator to answer one PING


def test_the_serving_thread_runs_at_realtime_priority(emulators):
    emulator = emulators("ttyRT", ids=[1])
    policy = os.sched_getscheduler(emulator.serving_thread_id)
    assert policy & ~os.SCHED_RESET_ON_FORK == os.SCHED_FIFO  # tests run as root: the raise is permitted


def test_without_realtime_the_serving_thread_keeps_normal_priority(emulators):
    emulator = emulators("ttyNORMAL", ids=[1], realtime=False)
    assert os.sched_getscheduler(emulator.serving_thread_id) == os.SCHED_OTHER


def test_a_reply_held_by_the_adapters_latency_timer_still_counts(emulators):
    emulator = emulators("ttyFTDI", ids=[1], adapter_latency_s=FTDI_LATENCY_TIMER_S)
    transport = SerialTransport(str(emulator.link), 1_000_000, max_retries=0)
    transport.open()
    try:
        assert FTDI_LATENCY_TIMER_S < REPLY_TIMEOUT_S
        assert transport.transact(proto.encode(1, proto.INST_PING), [Expected(1, 0)])[0].servo_id == 1
    finally:
        transport.close()


def test_scan_pings_every_id_through_an_adapter_with_a_latency_timer_when_the_broadcast_replies_are_garbled(
    emulators, capsys
):
    emulator = emulators("ttyFTDISCAN", ids=[3, 200], adapter_latency_s=FTDI_LATENCY_TIMER_S)
    emulator.corrupt_next_replies(1)  # the first broadcast reply arrives with a bad checksum
    code = main(["scan", str(emulator.link), "--json"])
    out, err = capsys.readouterr()
    assert (code, err) == (0, "")
    assert [servo["id"] for servo in json.loads(out)] == [3, 200]
    assert emulator.stats["packets"] > proto.MAX_SERVO_ID  # one PING per id at the noisy rate


def test_the_sweep_asks_a_silent_id_twice(emulators):
    emulator = emulators("ttySWEEP", ids=[3, 200])
    emulator.drop_next_replies(1)  # id 3's first answer is lost on the wire
    with open_bus(str(emulator.link)) as bus:  # a sweep of every id is the test above's; a few ids show the retry
        assert sorted(ping_every_id(bus, ids=[*range(8), 200])) == [3, 200]


class LateClock:
    """time.monotonic as a driver thread sees it when it is descheduled right after taking its deadline."""

    def __init__(self, late_s: float):
        self.late_s = late_s
        self.calls = 0

    def monotonic(self) -> float:
        self.calls += 1
        if self.calls == 1:
            return time.monotonic()
        if self.calls == 2:
            time.sleep(REPLY_LANDS_S)  # meanwhile the servo answers and the reply waits in the buffer
        return time.monotonic() + self.late_s


def test_a_reply_waiting_in_the_buffer_counts_when_the_driver_thread_ran_late(emulators, monkeypatch):
    emulator = emulators("ttyLATE", ids=[1])
    transport = SerialTransport(str(emulator.link), 1_000_000, max_retries=0)
    transport.open()
    try:
        monkeypatch.setattr(sts3215_transport, "time", LateClock(late_s=2 * REPLY_TIMEOUT_S))
        assert transport.transact(proto.encode(1, proto.INST_PING), [Expected(1, 0)])[0].servo_id == 1
    finally:
        transport.close()


def test_a_write_that_went_through_is_no_dead_port_when_the_driver_thread_ran_late(emulators, monkeypatch):
    emulator = emulators("ttyWRITE", ids=[1])
    transport = SerialTransport(str(emulator.link), 1_000_000, max_retries=0)
    transport.open()
    try:
        monkeypatch.setattr(serial.serialutil.Timeout, "TIME", LateClock(late_s=2 * WRITE_TIMEOUT_S).monotonic)
        assert transport.transact(proto.encode(1, proto.INST_PING), [Expected(1, 0)])[0].servo_id == 1
    finally:
        transport.close()
