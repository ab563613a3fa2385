"""Supervisor CPU and memory while one node floods its output: no newlines, against newlines every 80 bytes.

`measure(quick)` builds a one-node robot through plan() + render() and runs its supervisor.py
(stderr to /dev/null, node logs in a temporary directory). The node writes "flood start", waits to be
told to go, writes SIZE bytes in 64 KiB writes, then "flood done", and sleeps. The supervisor's CPU
(the kernel's scheduler time of its threads, /proc/PID/task/*/schedstat) is read when the node says
"flood start" and when "flood done" reaches its log file; its peak memory is VmHWM. The floor is the
same run with a newline every 80 bytes; `cat` reading the same bytes from a pipe into /dev/null (its
user+system time) shows what moving them costs at all.
"""

import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from google.protobuf import text_format

from joshua_codegen.plan import plan
from joshua_codegen.render import render
from joshua_codegen.write import write_tree
from joshua_core.schema import RobotDescription

SIZE_BYTES = 100 * 1024 * 1024
QUICK_SIZE_BYTES = 8 * 1024 * 1024
LINE_BYTES = 80  # the floor's line length
TIMEOUT_S = 300.0  # a flood not through the supervisor by then aborts the benchmark
POLL_S = 0.01
WRITE_BYTES = 65536

# argv: SIZE LINE_BYTES (0: no newline) GO_FILE [exit (when done, rather than sleep)]
FLOOD = r"""
import os, sys, time
size, line, go = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
os.write(1, b"flood start\n")
while not os.path.exists(go):
    time.sleep(0.005)
block = (b"x" * (line - 1) + b"\n") * (65536 // line) if line else b"x" * 65536
written = 0
while written < size:
    written += os.write(1, block[: size - written])
os.write(1, b"\nflood done\n")
if sys.argv[4:] != ["exit"]:
    time.sleep(3600)
"""


def quoted(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def cpu_seconds(pid: int) -> float:
    """CPU time of every thread of `pid` so far, from the scheduler's nanosecond counts."""
    total = 0
    for task in Path(f"/proc/{pid}/task").iterdir():
        total += int((task / "schedstat").read_text().split()[0])
    return total / 1e9


def peak_memory_mib(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def log_ends_with(path: Path, text: bytes) -> bool:
    try:
        with open(path, "rb") as log:
            log.seek(max(0, path.stat().st_size - len(text)))
            return log.read() == text
    except OSError:
        return False


def wait_for(predicate, what: str, deadline: float) -> None:
    while not predicate():
        if time.monotonic() > deadline:
            raise TimeoutError(f"no {what} within {TIMEOUT_S} s")
        time.sleep(POLL_S)


def supervisor_run(directory: Path, size: int, line: int) -> tuple[float, float]:
    """(supervisor CPU-s while the node writes `size` bytes, its peak memory in MiB)."""
    go, logs = directory / f"go-{line}", directory / f"logs-{line}"
    args = ", ".join(quoted(arg) for arg in ["-c", FLOOD, str(size), str(line), str(go)])
    config = (
        'robot_config { name: "flood" mode: MODE_TELEOPERATION\n'
        f'  node {{ name: "flood" type: CUSTOM executable: "{sys.executable}" args: [{args}] }}\n}}'
    )
    out = directory / f"out-{line}"
    write_tree(render(plan(text_format.Parse(config, RobotDescription()), "flood.pbtxt")), out)
    command = [sys.executable, str(out / "supervisor.py"), "--skip-preflight", "--no-control", "--log-dir", str(logs)]
    supervisor = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + TIMEOUT_S
        wait_for(lambda: log_ends_with(logs / "flood.log", b"flood start\n"), "flood start", deadline)
        before = cpu_seconds(supervisor.pid)
        go.touch()
        wait_for(lambda: log_ends_with(logs / "flood.log", b"flood done\n"), "flood done", deadline)
        return cpu_seconds(supervisor.pid) - before, peak_memory_mib(supervisor.pid)
    finally:
        supervisor.send_signal(signal.SIGINT)
        try:
            supervisor.wait(TIMEOUT_S)
        except subprocess.TimeoutExpired:
            supervisor.kill()
            supervisor.wait()


def cat_run(directory: Path, size: int) -> float:
    """CPU-s of `cat` reading the flood (no newlines) from a pipe into /dev/null."""
    go = directory / "go-cat"
    go.touch()
    with open(os.devnull, "wb") as devnull:
        cat = subprocess.Popen(["cat"], stdin=subprocess.PIPE, stdout=devnull)
        flood = subprocess.Popen([sys.executable, "-c", FLOOD, str(size), "0", str(go), "exit"], stdout=cat.stdin)
        cat.stdin.close()
        try:
            flood.wait(TIMEOUT_S)
            _, _, usage = os.wait4(cat.pid, 0)  # cat ends at the end of the pipe
        finally:
            flood.kill()
            cat.kill()
    return usage.ru_utime + usage.ru_stime


def measure(quick: bool = False) -> dict[str, float]:
    """Print and return the figures of one run (QUICK_SIZE_BYTES when `quick`, else SIZE_BYTES)."""
    size = QUICK_SIZE_BYTES if quick else SIZE_BYTES
    with tempfile.TemporaryDirectory(prefix="bench-output-flood-") as tmp:
        flood_cpu, flood_memory = supervisor_run(Path(tmp), size, 0)
        floor_cpu, floor_memory = supervisor_run(Path(tmp), size, LINE_BYTES)
        cat_cpu = cat_run(Path(tmp), size)
    mib = size / 2**20
    print(f"supervisor.py while one node writes {mib:.0f} MiB (CPU-s of the supervisor, its peak memory):")
    print(f"  without a newline        {flood_cpu:7.3f} CPU-s  {flood_memory:6.1f} MiB")
    print(f"  a newline every {LINE_BYTES} bytes {floor_cpu:7.3f} CPU-s  {floor_memory:6.1f} MiB  (floor)")
    print(f"  cat from a pipe          {cat_cpu:7.3f} CPU-s")
    print(f"  without newlines / floor {flood_cpu / floor_cpu:7.2f}x")
    return {"flood_cpu_s": flood_cpu, "floor_cpu_s": floor_cpu, "cat_cpu_s": cat_cpu, "flood_peak_mib": flood_memory}
