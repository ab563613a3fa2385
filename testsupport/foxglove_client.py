"""A Foxglove WebSocket client for tests and benches: connect, subscribe to topics, read their messages."""

import asyncio
import json
import re
import socket
import struct

import websockets

SUBPROTOCOL = "foxglove.sdk.v1"  # what foxglove-sdk 0.30 servers speak (the Foxglove app offers it)
MESSAGE_DATA_OPCODE = 0x01
WAIT_S = 30.0
# foxglove-sdk 0.30 has refused a subscription sent as soon as the channel's advertisement came, as "Unknown
# channel ID" (twice in one run of the suite on a loaded machine): the subscription is asked for again after a
# moment, as often as this.
RESUBSCRIBE_AFTER_S = 0.1
RESUBSCRIBE_TIMES = 20
UNKNOWN_CHANNEL = re.compile(r"Unknown channel ID: (\d+)")


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


async def connect(port: int, wait_s: float = WAIT_S):
    """A connection to the server on `port`, retried until it listens (at most `wait_s`)."""
    deadline = asyncio.get_running_loop().time() + wait_s
    while True:
        try:
            return await websockets.connect(f"ws://127.0.0.1:{port}", subprotocols=[SUBPROTOCOL], max_size=None)
        except OSError:
            if asyncio.get_running_loop().time() > deadline:
                raise
            await asyncio.sleep(0.2)


async def messages(socket_, topics: list[str], channels: dict):
    """Yields (topic, payload) of every message on `topics`, subscribing to each as it is advertised;
    `channels` collects every advertised channel by topic."""
    subscribed: dict[int, str] = {}
    requests: dict[int, dict] = {}  # by channel id, the subscribe request sent for it
    refused = 0
    while True:
        frame = await socket_.recv()
        if isinstance(frame, str):
            message = json.loads(frame)
            unknown = UNKNOWN_CHANNEL.fullmatch(message.get("message", "")) if message["op"] == "status" else None
            request = requests.get(int(unknown.group(1))) if unknown else None
            if request is not None and refused < RESUBSCRIBE_TIMES:
                refused += 1
                await asyncio.sleep(RESUBSCRIBE_AFTER_S)
                await socket_.send(json.dumps(request))
            if message["op"] != "advertise":
                continue
            for channel in message["channels"]:
                channels[channel["topic"]] = channel
                if channel["topic"] in topics and channel["topic"] not in subscribed.values():
                    subscription = len(subscribed) + 1
                    subscribed[subscription] = channel["topic"]
                    request = {"op": "subscribe", "subscriptions": [{"id": subscription, "channelId": channel["id"]}]}
                    requests[channel["id"]] = request
                    await socket_.send(json.dumps(request))
        elif frame[0] == MESSAGE_DATA_OPCODE:
            subscription, _log_time = struct.unpack_from("<IQ", frame, 1)
            yield subscribed[subscription], frame[13:]


async def first_messages(port: int, topics: list[str], wait_s: float = WAIT_S) -> tuple[dict, dict]:
    """(advertised channel by topic, first payload by topic) once every topic has sent a message."""
    deadline = asyncio.get_running_loop().time() + wait_s
    channels, payloads = {}, {}
    async with await connect(port, wait_s) as socket_:
        stream = messages(socket_, topics, channels)
        while len(payloads) < len(topics):
            topic, payload = await asyncio.wait_for(anext(stream), deadline - asyncio.get_running_loop().time())
            payloads.setdefault(topic, bytes(payload))
    return channels, payloads
