"""An STS3215 emulator in a process of its own: the in-process API, and replies that need no interpreter lock."""

import os
import subprocess
import sys
import threading

import pytest

from joshua_runtime.drivers import sts3215_protocol as proto
from joshua_runtime.drivers.sts3215 import Sts3215Driver
from joshua_runtime.drivers.sts3215_transport import Expected, SerialTransport
from joshua_runtime.emulators.sts3215_process import EmulatorProcessError, Sts3215EmulatorProcess

PINGS = 500
HOG = "while 1: pass"
HOGS_PER_CORE = 3  # a machine as busy as a full test run
WAIT_S = 2.0


@pytest.fixture
def bus(tmp_path):
    with Sts3215EmulatorProcess(tmp_path / "ttyCHILD", ids=[1, 2]) as emulator:
        yield emulator


def test_the_in_process_api_reaches_the_child(bus):
    writes, packets = [], []
    bus.write_listeners.append(lambda *event: writes.append(event))
    bus.packet_listeners.append(lambda packet, now: packets.append(packet.code))
    bus.move_by_hand(2, 3000)
    with Sts3215Driver(str(bus.link), [1, 2]) as driver:
        assert driver.read(2, "Present_Position") == 3000
        driver.write(1, "Acceleration", 9)
    assert bus.read_register(1, "Acceleration") == 9
    assert bus.wait_until(lambda: any(event[1] == 41 and event[2] == b"\x09" for event in writes), WAIT_S), writes
    assert proto.INST_PING in packets and bus.stats["packets"] >= len(packets) > 0
    assert bus.ids == [1, 2] and os.readlink(bus.link) == bus.device_name
    with pytest.raises(KeyError, match="no emulated servo with id 7"):
        bus.position(7)


def test_stop_ends_the_child_and_keeps_the_servos_for_the_next_start(tmp_path):
    emulator = Sts3215EmulatorProcess(tmp_path / "ttyGONE", ids=[1])
    with pytest.raises(EmulatorProcessError, match="ttyGONE has not started"):
        emulator.position(1)
    emulator.start().move_by_hand(1, 1000)
    child = emulator._child
    emulator.stop()
    assert child.returncode is not None and not emulator.link.exists()
    assert emulator.position(1) == 1000  # read as after unplugging an adapter
    with emulator:
        with Sts3215Driver(str(emulator.link), [1]) as driver:
            assert driver.read(1, "Present_Position") == 1000


def test_replies_need_no_interpreter_lock_of_the_host(bus):
    """A host thread that runs Python without pause, on a machine whose every core is busy: each PING is
    answered within the driver's attempts (an emulator in the host process missed all four of some)."""
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            pass

    spinner = threading.Thread(target=spin)
    spinner.start()
    hogs = [subprocess.Popen([sys.executable, "-c", HOG]) for _ in range(HOGS_PER_CORE * os.cpu_count())]
    transport, answered = SerialTransport(str(bus.link), 1_000_000), 0
    try:
        transport.open()
        for _ in range(PINGS):
            transport.transact(proto.encode(1, proto.INST_PING), [Expected(1, 0)])  # NoAnswer after 4 misses
            answered += 1
    finally:
        transport.close()
        for hog in hogs:
            hog.kill()
            hog.wait()
        stop.set()
        spinner.join()
    assert answered == PINGS
