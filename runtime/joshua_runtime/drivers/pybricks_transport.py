"""How the Pybricks driver reaches a hub: a small BLE transport interface, and its bleak implementation.

A transport finds and connects to one hub (by name, or by address when `hub` looks like one),
subscribes to the command/event characteristic, reads the capabilities, writes commands, and
reports a dropped link by calling `on_disconnect` with the reason in words. bleak uses the computer's own Bluetooth adapter;
pybricks_bumble.py implements the same interface over a Bumble BLE stack (a USB dongle, or an
emulated hub over HCI on TCP).
"""

from collections.abc import Callable

from joshua_core.devices import BLE_ADDRESS
from joshua_runtime.drivers.pybricks_protocol import CAPABILITIES_UUID, COMMAND_EVENT_UUID
from joshua_runtime.errors import DeviceError

SCAN_TIMEOUT_S = 10.0


def is_address(hub: str) -> bool:
    """`hub` is a Bluetooth address (else it is the hub's advertised name)."""
    return bool(BLE_ADDRESS.fullmatch(hub))


class HubTransport:
    """One BLE link to a Pybricks hub. Every method is a coroutine of the driver's event loop."""

    async def connect(self, hub: str, on_event: Callable[[bytes], None], on_disconnect: Callable[[str], None]) -> None:
        """Find and connect to `hub`, deliver every command/event notification to `on_event`."""
        raise NotImplementedError

    async def read_capabilities(self) -> bytes:
        raise NotImplementedError

    async def write_command(self, data: bytes) -> None:
        """Write one command to the command/event characteristic (with response)."""
        raise NotImplementedError

    async def disconnect(self) -> None:
        raise NotImplementedError

    async def reset(self) -> None:
        """Drop the link and whatever holds it open, so that the next connect() starts afresh."""
        await self.disconnect()

    async def close(self) -> None:
        """Release the link for good."""
        await self.reset()


class BleakTransport(HubTransport):
    """The computer's Bluetooth adapter through bleak (BlueZ on Linux); needs the `lego` extra."""

    client = None

    async def connect(self, hub, on_event, on_disconnect) -> None:
        try:
            from bleak import BleakClient, BleakScanner
            from bleak.exc import BleakError
        except ImportError:
            raise DeviceError("bleak is not installed: install joshua-runtime[lego]") from None
        try:
            if is_address(hub):
                device = await BleakScanner.find_device_by_address(hub, timeout=SCAN_TIMEOUT_S)
            else:
                device = await BleakScanner.find_device_by_name(hub, timeout=SCAN_TIMEOUT_S)
            if device is None:
                raise DeviceError(f"no Pybricks hub {hub!r} found within {SCAN_TIMEOUT_S:g} s")
            self.client = BleakClient(device, disconnected_callback=lambda _client: on_disconnect("disconnected"))
            await self.client.connect()
            await self.client.start_notify(COMMAND_EVENT_UUID, lambda _char, data: on_event(bytes(data)))
        except (FileNotFoundError, ConnectionRefusedError) as exc:
            raise DeviceError(
                f"no Bluetooth through BlueZ here (D-Bus: {exc}); is bluetoothd running? "
                "Set ble_transport to use a controller directly"
            ) from None
        except (BleakError, OSError) as exc:
            raise DeviceError(f"cannot connect to Pybricks hub {hub!r}: {exc}") from None

    async def read_capabilities(self) -> bytes:
        return bytes(await self.client.read_gatt_char(CAPABILITIES_UUID))

    async def write_command(self, data: bytes) -> None:
        await self.client.write_gatt_char(COMMAND_EVENT_UUID, data, response=True)

    async def disconnect(self) -> None:
        if self.client is not None:
            client, self.client = self.client, None
            await client.disconnect()
