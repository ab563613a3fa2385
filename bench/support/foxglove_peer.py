"""The Foxglove bridge as the dashboard's peer: its CPU while one Foxglove client takes the same streams, and
how old each message is when that client has it (receive time - header stamp).

The bridge is the robot's FOXGLOVE_BRIDGE node from the same build (nodes/foxglove_bridge.py), started
for its measurement alone and stopped after it; its client subscribes to every published topic and
reads every message, as the Foxglove app does.
"""

import asyncio
import struct
import subprocess
import sys
import time
from pathlib import Path

from support.process_usage import cpu_seconds
from testsupport.foxglove_client import connect, messages
from testsupport.node_process import stop_process

BRIDGE_PROCESS = "foxglove_bridge"
READY_TIMEOUT_S = 60.0
CDR_HEADER_BYTES = 4  # the encapsulation before a serialized message's first field
STAMP = struct.Struct("<iI")  # builtin_interfaces/Time, little-endian CDR


def foxglove_block(port: int) -> str:
    """The description's block that adds the bridge, listening on loopback."""
    return f'  foxglove {{ port: {port} bind: "127.0.0.1" }}\n'


def stamp_ns(payload: bytes) -> int:
    """The header stamp of a CDR message whose first field is a std_msgs/Header (JointState, Image)."""
    sec, nanosec = STAMP.unpack_from(payload, CDR_HEADER_BYTES)
    return sec * 1_000_000_000 + nanosec


async def _measure(pid: int, port: int, topics: list[str], seconds: float) -> tuple[float, dict, dict]:
    counts = dict.fromkeys(topics, 0)
    async with await connect(port, READY_TIMEOUT_S) as socket_:
        stream = messages(socket_, topics, {})
        deadline = time.monotonic() + READY_TIMEOUT_S
        while not all(counts.values()):  # every stream flows before the measurement starts
            topic, _ = await asyncio.wait_for(anext(stream), deadline - time.monotonic())
            counts[topic] += 1
        counts = dict.fromkeys(topics, 0)
        latency_ms = {topic: [] for topic in topics}
        before, start = cpu_seconds(pid), time.monotonic()
        while (left := start + seconds - time.monotonic()) > 0:
            try:
                topic, payload = await asyncio.wait_for(anext(stream), left)
            except TimeoutError:
                break
            latency_ms[topic].append((time.time_ns() - stamp_ns(payload)) / 1e6)
            counts[topic] += 1
        elapsed = time.monotonic() - start
        cpu = 100.0 * (cpu_seconds(pid) - before) / elapsed
    return cpu, {topic: count / elapsed for topic, count in counts.items()}, latency_ms


def bridge_cpu_percent(out: Path, port: int, topics: list[str], seconds: float) -> tuple[float, dict, dict]:
    """(the bridge's CPU % over `seconds` with one client, messages/s that client got per topic, the age in ms
    of each message it got, per topic)."""
    bridge = subprocess.Popen(
        [sys.executable, str(out / "nodes" / f"{BRIDGE_PROCESS}.py")],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        return asyncio.run(_measure(bridge.pid, port, topics, seconds))
    except (OSError, TimeoutError) as exc:
        _, _, stderr = stop_process(bridge)
        raise SystemExit(f"the Foxglove bridge did not serve: {exc}; {stderr[-2000:]}") from None
    finally:
        stop_process(bridge)
