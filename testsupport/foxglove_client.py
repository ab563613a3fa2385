"""A Foxglove WebSocket client for tests: connect, subscribe to topics, collect their first messages."""

import asyncio
import json
import socket
import struct

import websockets

SUBPROTOCOL = "foxglove.sdk.v1"  # what foxglove-sdk 0.30 servers speak (the Foxglove app offers it)
MESSAGE_DATA_OPCODE = 0x01
WAIT_S = 30.0


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


async def first_messages(port: int, topics: list[str], wait_s: float = WAIT_S) -> tuple[dict, dict]:
    """(advertised channel by topic, first payload by topic) once every topic has sent a message."""
    deadline = asyncio.get_running_loop().time() + wait_s
    while True:
        try:
            socket_ = await websockets.connect(f"ws://127.0.0.1:{port}", subprotocols=[SUBPROTOCOL])
            break
        except OSError:
            if asyncio.get_running_loop().time() > deadline:
                raise
            await asyncio.sleep(0.2)
    channels, payloads, subscribed = {}, {}, {}
    async with socket_:
        while len(payloads) < len(topics):
            frame = await asyncio.wait_for(socket_.recv(), deadline - asyncio.get_running_loop().time())
            if isinstance(frame, str):
                message = json.loads(frame)
                if message["op"] == "advertise":
                    for channel in message["channels"]:
                        channels[channel["topic"]] = channel
                        if channel["topic"] in topics and channel["topic"] not in subscribed.values():
                            subscription = len(subscribed) + 1
                            subscribed[subscription] = channel["topic"]
                            await socket_.send(
                                json.dumps(
                                    {
                                        "op": "subscribe",
                                        "subscriptions": [{"id": subscription, "channelId": channel["id"]}],
                                    }
                                )
                            )
            elif frame[0] == MESSAGE_DATA_OPCODE:
                subscription, _log_time = struct.unpack_from("<IQ", frame, 1)
                payloads.setdefault(subscribed[subscription], bytes(frame[13:]))
    return channels, payloads
