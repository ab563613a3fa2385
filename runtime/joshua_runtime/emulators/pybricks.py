"""An emulated Pybricks hub on a Bumble BLE stack: the Pybricks GATT service plus two wheel motors.

It takes a program download (write meta, write RAM, write meta again) and checks that it is a
multi-file blob with an MPY v6 `__main__`; on start it runs, instead of executing MicroPython, the
line protocol of the hub program (drivers/pybricks_protocol.py) over its stdin/stdout with the
motor model of pybricks_motors.py, including the program's own watchdog. Faults on request: a hub
that never starts its program, garbage written to stdout, the link dropped mid-command; each one
injected is told to `report` (the command line prints it), garbage at most every REPORT_INTERVAL_S.
"""

import asyncio
import random
import struct
import time
from collections.abc import Callable
from dataclasses import dataclass

from bumble.att import ATT_DEFAULT_MTU, ATT_Error, Attribute
from bumble.core import UUID, AdvertisingData
from bumble.device import Connection, Device
from bumble.gatt import Characteristic, CharacteristicValue, Service

from joshua_runtime.drivers import pybricks_protocol as hub
from joshua_runtime.drivers.pybricks_program import MPY_V6_MAGIC, main_module
from joshua_runtime.emulators.pybricks_motors import Motor

HUB_ADDRESS = "F4:B8:5E:00:00:01"
MAX_WRITE = 158
MAX_PROGRAM = 32 * 1024
TICK_S = 0.005
# Shortest interval BLE allows, so that scans and connections take milliseconds.
ADVERTISING_INTERVAL_MS = 20.0
# Pybricks error codes answered to a command the hub cannot take now.
ERROR_BUSY = 0x81
ERROR_INVALID_COMMAND = 0x80
ERROR_VALUE_NOT_ALLOWED = 0x13
GARBAGE = b"\x00\xff*\n#A,1,2*ZZ\nK,x*00\r\n\xfe\x80\n"
# Garbage is injected many times a second; its reports are summed up this often.
REPORT_INTERVAL_S = 1.0


@dataclass
class HubFaults:
    never_start: bool = False  # START_PROGRAM is accepted, the program never runs
    garbage_rate: float = 0.0  # fraction of stdout writes preceded by garbage bytes
    drop_link_after: int = 0  # drop the link on this stdin command (0: never)
    seed: int = 0


class EmulatedHub:
    """The hub side: GATT server, program state, line protocol and motors, on a Bumble Device."""

    def __init__(
        self,
        device: Device,
        name: str = hub.DEFAULT_HUB_NAME,
        faults: HubFaults | None = None,
        report: Callable[[str], None] = lambda _text: None,
    ):
        self.device, self.name, self.report = device, name, report
        self.faults = faults or HubFaults()
        self.garbage_lines = self.stdout_lines = 0
        self._next_garbage_report = 0.0
        self.random = random.Random(self.faults.seed)
        self.left, self.right = Motor(), Motor()
        self.ram = bytearray()
        self.program = b""
        self.running = False
        self.commands = 0
        self.connection: Connection | None = None
        self.lines = hub.LineAssembler()
        self._last_command = self._next_report = 0.0
        self._started_at = time.monotonic()
        self._task: asyncio.Task | None = None
        self.command_event = Characteristic(
            hub.COMMAND_EVENT_UUID,
            Characteristic.Properties.WRITE
            | Characteristic.Properties.WRITE_WITHOUT_RESPONSE
            | Characteristic.Properties.NOTIFY,
            Attribute.Permissions.WRITEABLE,
            CharacteristicValue(write=self._on_write),
        )
        capabilities = hub.pack_capabilities(hub.Capabilities(MAX_WRITE, 0b10, MAX_PROGRAM, 1))
        self.capabilities = Characteristic(
            hub.CAPABILITIES_UUID, Characteristic.Properties.READ, Attribute.Permissions.READABLE, capabilities
        )
        device.add_service(Service(hub.SERVICE_UUID, [self.command_event, self.capabilities]))
        device.on(Device.EVENT_CONNECTION, self._on_connection)
        self.command_event.on(Characteristic.EVENT_SUBSCRIPTION, self._on_subscription)

    async def start(self) -> None:
        """Power on, advertise (again after every disconnection) and run the motors."""
        await self.device.power_on()
        advertising = AdvertisingData(
            [
                (AdvertisingData.COMPLETE_LOCAL_NAME, self.name.encode()),
                (AdvertisingData.INCOMPLETE_LIST_OF_128_BIT_SERVICE_CLASS_UUIDS, UUID(hub.SERVICE_UUID).to_bytes()),
            ]
        )
        await self.device.start_advertising(
            auto_restart=True,
            advertising_data=bytes(advertising),
            advertising_interval_min=ADVERTISING_INTERVAL_MS,
            advertising_interval_max=ADVERTISING_INTERVAL_MS,
        )
        self._task = asyncio.get_running_loop().create_task(self._run())

    async def stop(self) -> None:
        if self._task is not None:
            self._task.cancel()
        await self.device.power_off()

    # --- GATT -----------------------------------------------------------------------------------

    def _on_connection(self, connection: Connection) -> None:
        self.connection = connection
        connection.on(Connection.EVENT_DISCONNECTION, lambda _reason: setattr(self, "connection", None))

    def _on_subscription(self, *_args) -> None:
        self._send_status()

    def _on_write(self, _connection, value: bytes) -> None:
        if not value:
            raise ATT_Error(ERROR_INVALID_COMMAND)
        command, body = value[0], bytes(value[1:])
        if command == hub.CMD_WRITE_STDIN:
            self._on_stdin(body)
        elif command == hub.CMD_STOP_PROGRAM:
            self._set_running(False)
        elif self.running:
            raise ATT_Error(ERROR_BUSY)
        elif command == hub.CMD_WRITE_PROGRAM_META and len(body) == 4:
            self._on_meta(struct.unpack("<I", body)[0])
        elif command == hub.CMD_WRITE_RAM and len(body) >= 4:
            offset = struct.unpack_from("<I", body)[0]
            if offset + len(body) - 4 > MAX_PROGRAM:
                raise ATT_Error(ERROR_VALUE_NOT_ALLOWED)
            self.ram[offset : offset + len(body) - 4] = body[4:]
        elif command == hub.CMD_START_PROGRAM:
            mpy = main_module(self.program)
            if mpy is None or not mpy.startswith(MPY_V6_MAGIC):
                raise ATT_Error(ERROR_VALUE_NOT_ALLOWED)
            if self.faults.never_start:
                self.report("fault: program accepted, never started (--never-start)")
            else:
                self._set_running(True)
        else:
            raise ATT_Error(ERROR_INVALID_COMMAND)

    def _on_meta(self, size: int) -> None:
        if size > MAX_PROGRAM:
            raise ATT_Error(ERROR_VALUE_NOT_ALLOWED)
        if size == 0:
            self.ram, self.program = bytearray(), b""
        else:
            self.program = bytes(self.ram[:size])

    def _set_running(self, running: bool) -> None:
        if running == self.running:
            return
        self.running = running
        self.left.stop()
        self.right.stop()
        if running:
            self._last_command = self._next_report = time.monotonic()
            self._write_stdout(hub.encode_line("R"))
        self._send_status()

    def _send_status(self) -> None:
        flags = hub.STATUS_PROGRAM_RUNNING if self.running else 0
        self._notify(hub.status_event(flags))

    def _notify(self, value: bytes) -> None:
        if self.connection is not None:
            asyncio.get_running_loop().create_task(self.device.notify_subscribers(self.command_event, value))

    # --- the hub program ------------------------------------------------------------------------

    def _on_stdin(self, data: bytes) -> None:
        if not self.running:
            return
        for fields in self.lines.feed(data):
            self.commands += 1
            if self.faults.drop_link_after and self.commands == self.faults.drop_link_after:
                self.report(f"fault: dropping the link on stdin command {self.commands} (--drop-link-after)")
                asyncio.get_running_loop().create_task(self._drop_link())
                return
            if fields[0] == "V" and len(fields) == 4:
                try:
                    left, right = float(fields[2]), float(fields[3])
                except ValueError:
                    continue
                self.left.run(left)
                self.right.run(right)
            elif fields[0] == "S" and len(fields) == 2:
                self.left.stop()
                self.right.stop()
            else:
                continue
            self._last_command = time.monotonic()
            self._write_stdout(hub.encode_line("K", fields[1]))

    async def _drop_link(self) -> None:
        if self.connection is not None:
            await self.connection.disconnect()

    def _write_stdout(self, line: bytes) -> None:
        self.stdout_lines += 1
        if self.faults.garbage_rate and self.random.random() < self.faults.garbage_rate:
            start = self.random.randrange(len(GARBAGE))
            line = GARBAGE[start:] + line
            self.garbage_lines += 1
            if time.monotonic() >= self._next_garbage_report:
                self._next_garbage_report = time.monotonic() + REPORT_INTERVAL_S
                self.report(
                    f"fault: garbage before {self.garbage_lines} of {self.stdout_lines} stdout lines so far "
                    "(--garbage-rate)"
                )
        mtu = self.connection.att_mtu if self.connection is not None else ATT_DEFAULT_MTU
        chunk = mtu - 3 - 1
        for offset in range(0, len(line), chunk):
            self._notify(bytes([hub.EVENT_STDOUT]) + line[offset : offset + chunk])

    async def _run(self) -> None:
        last = time.monotonic()
        while True:
            await asyncio.sleep(TICK_S)
            now = time.monotonic()
            self.left.step(now - last)
            self.right.step(now - last)
            last = now
            if not self.running:
                continue
            if now - self._last_command > hub.HUB_WATCHDOG_MS / 1000:
                self.left.stop()
                self.right.stop()
                self._last_command = now
            if now >= self._next_report:
                hub_ms = int((now - self._started_at) * 1000)
                self._write_stdout(
                    hub.encode_line("A", hub_ms, round(self.left.angle_deg), round(self.right.angle_deg))
                )
                self._next_report = now + hub.REPORT_PERIOD_MS / 1000
