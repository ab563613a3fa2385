"""Start and stop times of the generated supervisor.py beside dora, supervisord and circus running the same nodes.

    .venv/bin/python bench/supervisor.py [--runs 5] [--sizes 1,8,32,100] [--quick]

For 1, 8, 32 and 100 cooperative CUSTOM nodes (`sh` that reports its pid on a FIFO, then execs `sleep`,
which exits on SIGINT), built once through plan() + render(): the time from launching the manager to
every node running (all pids read from the FIFO), and from SIGINT to the manager's exit after every
node exited. supervisord runs `supervisord -c OUT/supervisord.conf` (foreground, as generated, with its
critical-node event listener); `dora run` (dora-rs-cli, a Rust program) a dataflow of the same commands;
circus `circusd` an ini file of one watcher per node, stopped by SIGINT, its endpoints on Unix sockets.
The managers take turns within each run, so all see the same machine load. Medians (and the range) of
--runs runs; "x" is the peer's time over supervisor.py's (above 1: supervisor.py is faster); "per node"
is the marginal cost of one more node between the smallest and the largest size. supervisor.py runs as on a
robot after its first start, its code compiled once and kept in the user's cache (a cache of the run's own,
PYTHONDONTWRITEBYTECODE unset); that first start of each size is timed apart and left out of the medians.
"""

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from google.protobuf import text_format  # noqa: E402

from joshua_codegen.emitters.supervisor import INTERPRETER_FLAGS  # noqa: E402
from joshua_codegen.plan import plan  # noqa: E402
from joshua_codegen.render import render  # noqa: E402
from joshua_codegen.write import write_tree  # noqa: E402
from joshua_core.schema import RobotDescription  # noqa: E402

BIN = Path(sys.executable).parent
NODE_SCRIPT = 'echo $$ > "$1"; exec sleep 3600'
TIMEOUT_S = 30.0  # any single start or stop taking longer than this aborts the benchmark


def quoted(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def description(nodes: int, fifo: Path) -> str:
    lines = ['robot_config { name: "bench" mode: MODE_TELEOPERATION shutdown { sigint_grace_s: 5 sigterm_grace_s: 2 }']
    args = ", ".join(quoted(arg) for arg in ["-c", NODE_SCRIPT, "sh", str(fifo)])
    for i in range(nodes):
        lines.append(f'  node {{ name: "sleeper{i}" type: CUSTOM executable: "/bin/sh" args: [{args}] }}')
    return "\n".join(lines + ["}"])


def dora_dataflow(nodes: int, fifo: Path) -> str:
    """The same commands as a dora dataflow: nodes without inputs or outputs, spawned as they are."""
    args = " ".join(["-c", f"'{NODE_SCRIPT}'", "sh", str(fifo)])
    return "nodes:\n" + "".join(f"  - id: sleeper{i}\n    path: /bin/sh\n    args: {args}\n" for i in range(nodes))


def circus_ini(nodes: int, fifo: Path, sockets: Path) -> str:
    """The same commands as circus watchers, stopped with SIGINT like the generated managers stop them."""
    lines = [
        "[circus]",
        f"endpoint = ipc://{sockets}/control",
        f"pubsub_endpoint = ipc://{sockets}/pubsub",
        "statsd = False",
        "check_delay = 0",
    ]
    for i in range(nodes):
        lines += [
            f"[watcher:sleeper{i}]",
            "cmd = /bin/sh",
            f"args = -c '{NODE_SCRIPT}' sh {fifo}",
            "numprocesses = 1",
            "stop_signal = INT",
            "copy_env = True",
        ]
    return "\n".join(lines) + "\n"


def read_pids(fifo_fd: int, count: int, deadline: float) -> list[int]:
    buffer = b""
    while buffer.count(b"\n") < count:
        if time.monotonic() > deadline:
            raise TimeoutError(f"only {len(buffer.split())} of {count} nodes reported within {TIMEOUT_S} s")
        try:
            chunk = os.read(fifo_fd, 4096)
        except BlockingIOError:
            time.sleep(0.0005)
            continue
        buffer += chunk
    return [int(line) for line in buffer.split()]


def gone(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return True
    return state == "Z"


def measure(command: list[str], fifo: Path, count: int, cwd: Path, env: dict[str, str]) -> tuple[float, float]:
    """(seconds to every node running, seconds from SIGINT to the manager's exit with every node gone)."""
    fifo_fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    keep_open = os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)  # no EOF between writers
    started = time.monotonic()
    manager = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=cwd, env=env)
    try:
        pids = read_pids(fifo_fd, count, started + TIMEOUT_S)
        running = time.monotonic() - started
        time.sleep(0.2)  # let the manager settle before asking it to stop
        stopping = time.monotonic()
        manager.send_signal(signal.SIGINT)
        manager.wait(TIMEOUT_S)
        stopped = time.monotonic() - stopping
        if not all(gone(pid) for pid in pids):
            raise RuntimeError("a node outlived its manager")
        return running, stopped
    finally:
        if manager.poll() is None:
            manager.kill()
            manager.wait()
        os.close(fifo_fd)
        os.close(keep_open)


def managers(out: Path) -> dict[str, list[str]]:
    return {
        "supervisor.py": [sys.executable, *INTERPRETER_FLAGS, str(out / "supervisor.py")],  # as the launchers run it
        "dora": [str(BIN / "dora"), "run", str(out / "dataflow.yml")],
        "supervisord": [str(BIN / "supervisord"), "-c", str(out / "supervisord.conf")],
        "circus": [str(BIN / "circusd"), str(out / "circus.ini")],
    }


def write_configs(tmp: Path, size: int, fifo: Path) -> Path:
    out = tmp / "out"
    robot = plan(text_format.Parse(description(size, fifo), RobotDescription()), "bench.pbtxt")
    write_tree(render(robot, prefix=str(out)), out)
    (out / "dataflow.yml").write_text(dora_dataflow(size, fifo))
    (out / "circus.ini").write_text(circus_ini(size, fifo, tmp))
    return out


def bench(sizes: list[int], runs: int) -> None:
    names = list(managers(Path()))
    samples: dict[tuple[str, int], list[tuple[float, float]]] = {}
    first_starts: dict[int, float] = {}
    for size in sizes:
        with tempfile.TemporaryDirectory(prefix="bench-supervisor-") as tmp:
            fifo = Path(tmp) / "ready"
            os.mkfifo(fifo)
            commands = managers(write_configs(Path(tmp), size, fifo))
            env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"} | {"XDG_CACHE_HOME": tmp}
            first_starts[size] = measure(commands["supervisor.py"], fifo, size, Path(tmp), env)[0]
            for _ in range(runs):
                for name, command in commands.items():  # interleaved, so all see the same machine load
                    samples.setdefault((name, size), []).append(measure(command, fifo, size, Path(tmp), env))
    median = {key: tuple(statistics.median(s[i] for s in values) for i in (0, 1)) for key, values in samples.items()}
    print(f"{'nodes':>5}  {'manager':<14} {'start -> all running (range)':>34} {'x':>6} {'SIGINT -> all exited':>21}")
    for size in sizes:
        ours = median["supervisor.py", size][0]
        for name in names:
            running, stopped = median[name, size]
            starts = [s[0] for s in samples[name, size]]
            span = f"({min(starts) * 1000:.1f}-{max(starts) * 1000:.1f})"
            ratio = f"{running / ours:6.2f}" if name != "supervisor.py" else f"{'':>6}"
            print(f"{size:>5}  {name:<14} {running * 1000:>10.1f} ms {span:>20} {ratio} {stopped * 1000:>18.1f} ms")
    print(f"\nx: the manager's median start over supervisor.py's, {runs} runs taking turns")
    firsts = ", ".join(f"{size}: {seconds * 1000:.1f} ms" for size, seconds in first_starts.items())
    print(f"supervisor.py's first start after the build, compiling its code (nodes: start -> all running): {firsts}")
    if len(sizes) > 1:
        low, high = min(sizes), max(sizes)
        print(f"\nmarginal cost of one more node ({low} -> {high} nodes):")
        for name in names:
            start = (median[name, high][0] - median[name, low][0]) / (high - low)
            stop = (median[name, high][1] - median[name, low][1]) / (high - low)
            print(f"  {name:<14} start {start * 1000:6.2f} ms/node   stop {stop * 1000:6.2f} ms/node")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--sizes", default="1,8,32,100")
    # One size: dora takes 10 s to stop nodes that do not speak its protocol, at every size.
    parser.add_argument("--quick", action="store_true", help="one run of 2 nodes (for the tests)")
    options = parser.parse_args()
    if options.quick:
        options.runs, options.sizes = 1, "2"
    bench([int(size) for size in options.sizes.split(",")], options.runs)


if __name__ == "__main__":
    main()
