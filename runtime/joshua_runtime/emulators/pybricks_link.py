"""Where an emulated Pybricks hub lives: on an in-process Bumble link, or behind an HCI served on TCP.

Bumble's link between virtual controllers exists only inside one process. To reach the hub from
another process, `serve` puts a second virtual controller on the hub's link and serves that
controller's HCI on a TCP port of 127.0.0.1 (Bumble's `tcp-server` transport); the other process
runs its BLE host over `tcp-client:127.0.0.1:PORT` and sees an ordinary controller with one hub in
range. One client at a time.
"""

import asyncio

from bumble.controller import Controller
from bumble.device import Device
from bumble.hci import Address
from bumble.host import Host
from bumble.link import LocalLink
from bumble.transport import open_transport
from bumble.transport.common import AsyncPipeSink

from joshua_runtime.drivers.pybricks_bumble import CENTRAL_ADDRESS
from joshua_runtime.emulators.pybricks import HUB_ADDRESS, EmulatedHub, HubFaults

POLL_S = 0.05


def _device_on(link: LocalLink, name: str, address: str) -> Device:
    controller = Controller(name, link=link, public_address=address)
    return Device(name=name, address=Address(address), host=Host(controller, AsyncPipeSink(controller)))


async def in_process(
    name: str, faults: HubFaults | None = None, report=lambda _text: None
) -> tuple[EmulatedHub, Device]:
    """A started emulated hub and a powered-on central Device, both on one in-process link."""
    link = LocalLink()
    emulated = EmulatedHub(_device_on(link, "hub", HUB_ADDRESS), name, faults, report)
    await emulated.start()
    central = _device_on(link, "central", CENTRAL_ADDRESS)
    await central.power_on()
    return emulated, central


async def serve_hci(name: str, port: int, faults: HubFaults | None = None, report=lambda _text: None):
    """Start a hub and serve the HCI of a controller next to it on 127.0.0.1:port; returns (hub, transport)."""
    link = LocalLink()
    emulated = EmulatedHub(_device_on(link, "hub", HUB_ADDRESS), name, faults, report)
    await emulated.start()
    transport = await open_transport(f"tcp-server:127.0.0.1:{port}")
    Controller("host", host_source=transport.source, host_sink=transport.sink, link=link)
    return emulated, transport


def serve(args, should_stop) -> None:
    """`joshua-emulate pybricks`: serve until should_stop() says so."""
    faults = HubFaults(
        never_start=args.never_start,
        garbage_rate=args.garbage_rate,
        drop_link_after=args.drop_link_after,
        seed=args.seed,
    )

    def report(text: str) -> None:
        print(f"joshua-emulate: {text}", flush=True)

    async def main() -> None:
        emulated, transport = await serve_hci(args.name, args.port, faults, report)
        print(
            f"joshua-emulate: Pybricks hub {args.name!r} ({HUB_ADDRESS}) reachable over "
            f"hci tcp-client:127.0.0.1:{args.port}",
            flush=True,
        )
        while not should_stop():
            await asyncio.sleep(POLL_S)
        await transport.close()

    asyncio.run(main())
