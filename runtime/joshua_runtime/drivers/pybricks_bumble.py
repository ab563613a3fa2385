"""The Pybricks hub transport over a Bumble BLE stack (pure-Python host; HCI to any Bumble transport).

`hci` names where the controller is, in Bumble's transport syntax: `usb:0` for a USB Bluetooth dongle,
`tcp-client:127.0.0.1:PORT` for the controller `joshua-emulate pybricks` serves next to its emulated
hub. Tests hand in a Device already on an in-process link instead.

A controller that goes away (a dongle pulled out, the emulator restarted) ends the connection; `reset()`
then closes it, and the next `connect()` opens `hci` again. Bumble logs its own warnings and
tracebacks about commands to a dead controller; the driver reports the loss as one line instead.
"""

import asyncio
import logging

from bumble.core import UUID, AdvertisingData, BaseBumbleError
from bumble.device import Connection, Device, Peer
from bumble.hci import HCI_REMOTE_USER_TERMINATED_CONNECTION_ERROR, Address, HCI_Constant
from bumble.transport import open_transport

from joshua_runtime.drivers.pybricks_protocol import CAPABILITIES_UUID, COMMAND_EVENT_UUID, SERVICE_UUID
from joshua_runtime.drivers.pybricks_transport import SCAN_TIMEOUT_S, HubTransport, is_address
from joshua_runtime.errors import DeviceError

# The random static address this computer's side uses on the link.
CENTRAL_ADDRESS = "C0:4A:05:00:00:01"
# ATT MTU asked for, so that a whole stdin line or RAM chunk fits in one write.
ATT_MTU = 185
# A controller answers an HCI command in milliseconds; one that has not within this is gone.
HCI_COMMAND_TIMEOUT_S = 2.0
BUMBLE_ERRORS = (BaseBumbleError, asyncio.TimeoutError, OSError, ConnectionError)


def _silence_bumble() -> None:
    """Bumble's log goes nowhere: its warnings would repeat, in many lines, what the driver reports in one."""
    bumble_log = logging.getLogger("bumble")
    if not bumble_log.handlers:
        bumble_log.addHandler(logging.NullHandler())
    bumble_log.propagate = False


class BumbleTransport(HubTransport):
    """A Pybricks hub reached through a Bumble Device (central role)."""

    def __init__(self, hci: str = "", device: Device | None = None):
        self.hci_spec, self.device = hci, device
        self.owns_device = device is None  # it opens (and reopens) the controller named by `hci`
        self.hci = None
        self.connection: Connection | None = None
        self.command_event = self.capabilities = None
        _silence_bumble()

    async def _power_on(self) -> None:
        if self.device is not None:
            return
        try:
            self.hci = await open_transport(self.hci_spec)
        except BUMBLE_ERRORS as exc:
            raise DeviceError(f"cannot open Bluetooth controller {self.hci_spec!r}: {exc}") from None
        self.device = Device.with_hci("joshua", Address(CENTRAL_ADDRESS), self.hci.source, self.hci.sink)
        self.device.command_timeout = HCI_COMMAND_TIMEOUT_S
        try:
            await self.device.power_on()
        except BUMBLE_ERRORS as exc:
            raise DeviceError(f"Bluetooth controller {self.hci_spec!r} does not answer: {_reason(exc)}") from None

    def _disconnection(self, code: int) -> str:
        """Why a connection ended, in words."""
        if self.hci is not None and self.hci.source.terminated.done():
            return "Bluetooth controller lost"
        if code == HCI_REMOTE_USER_TERMINATED_CONNECTION_ERROR:
            return "the hub closed the link"
        return f"disconnected: {HCI_Constant.error_name(code)}"

    async def connect(self, hub, on_event, on_disconnect) -> None:
        await self._power_on()
        try:
            target = Address(hub) if is_address(hub) else await self._scan(hub)
            self.connection = await self.device.connect(target, timeout=SCAN_TIMEOUT_S)
            self.connection.on(Connection.EVENT_DISCONNECTION, lambda code: on_disconnect(self._disconnection(code)))
            peer = Peer(self.connection)
            await peer.request_mtu(ATT_MTU)
            await peer.discover_services([UUID(SERVICE_UUID)])
            await peer.discover_characteristics()
            self.command_event = _characteristic(peer, COMMAND_EVENT_UUID)
            self.capabilities = _characteristic(peer, CAPABILITIES_UUID)
            await self.command_event.subscribe(lambda value: on_event(bytes(value)))
        except BUMBLE_ERRORS as exc:
            raise DeviceError(f"cannot connect to Pybricks hub {hub!r}: {_reason(exc)}") from None

    async def _scan(self, name: str) -> Address:
        """The address of the first advertiser named `name`."""
        found = asyncio.get_running_loop().create_future()

        def on_advertisement(advertisement) -> None:
            if advertisement.data.get(AdvertisingData.COMPLETE_LOCAL_NAME) == name and not found.done():
                found.set_result(advertisement.address)

        self.device.on(Device.EVENT_ADVERTISEMENT, on_advertisement)
        try:
            await self.device.start_scanning(filter_duplicates=True)
            return await asyncio.wait_for(found, SCAN_TIMEOUT_S)
        except asyncio.TimeoutError:
            raise DeviceError(f"no Pybricks hub {name!r} found within {SCAN_TIMEOUT_S:g} s") from None
        finally:
            self.device.remove_listener(Device.EVENT_ADVERTISEMENT, on_advertisement)
            await self.device.stop_scanning()

    async def read_capabilities(self) -> bytes:
        return bytes(await self.capabilities.read_value())

    async def write_command(self, data: bytes) -> None:
        await self.command_event.write_value(data, with_response=True)

    async def disconnect(self) -> None:
        if self.connection is not None:
            try:
                await self.connection.disconnect()
            except BUMBLE_ERRORS:
                pass
            self.connection = None

    async def reset(self) -> None:
        """Disconnect and close the controller opened from `hci`; the next connect() opens it again.

        The controller is closed even when disconnecting hangs and is cancelled (a frozen controller).
        """
        try:
            if self.hci is None or not self.hci.source.terminated.done():
                await self.disconnect()
        finally:
            self.connection = None
            if self.hci is not None:
                hci, self.hci = self.hci, None
                if self.owns_device:
                    self.device = None
                await hci.close()

    async def close(self) -> None:
        await self.reset()


def _reason(exc: BaseException) -> str:
    return str(exc) or type(exc).__name__


def _characteristic(peer: Peer, uuid: str):
    found = peer.get_characteristics_by_uuid(UUID(uuid))
    if not found:
        raise DeviceError(f"the peer has no Pybricks characteristic {uuid}: is it a Pybricks hub?")
    return found[0]
