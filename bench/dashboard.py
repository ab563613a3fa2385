"""Dashboard figures: ROS publish -> browser DOM latency, server CPU per client, 10 clients, a stalled client.

    .venv/bin/python bench/dashboard.py [--quick]

This process publishes 30 Hz JointState and 15 fps 640x480 rgb8 Image messages stamped with the wall
clock; the dashboard server (python -m joshua_runtime.dashboard, on a joshuac build of a description
naming those topics) streams them. Latency: headless Chromium (Debian's, under Playwright) notes the
wall clock when the page's DOM shows a message's stamp. CPU: the server's utime+stime from /proc with
0, 1 and 10 SSE clients. Stalled: a client that sends its request and never reads; the server's RSS
is sampled while frames keep coming. --quick: 1 s per measurement, no warm-up beyond the first
message each client gets (for the tests).
"""

import argparse
import http.client
import os
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from support.foxglove_peer import bridge_cpu_percent, foxglove_block  # noqa: E402
from support.process_usage import cpu_seconds, cpu_seconds_of, descendants, rss_mib  # noqa: E402
from support.ros_env import bench_environment  # noqa: E402

from joshua_codegen.emitters.fastdds import IMAGES_PROFILE_PATH  # noqa: E402
from joshua_core.dashboard_token import token_path  # noqa: E402
from testsupport.foxglove_client import free_port  # noqa: E402
from testsupport.joshuac_cli import joshuac  # noqa: E402

JOINT_HZ, IMAGE_FPS, WIDTH, HEIGHT = 30.0, 15.0, 640, 480
JOINT_TOPIC, IMAGE_TOPIC = "/bench/joint_states", "/bench/image_raw"
TOPICS = [JOINT_TOPIC, IMAGE_TOPIC]
JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]
DESCRIPTION = f"""robot_config {{
  name: "bench_dashboard"
  mode: MODE_TELEOPERATION
  node {{ name: "arm" type: MOCK_ENCODER_PUBLISHER topic_name: "{JOINT_TOPIC}" rate_hz: {JOINT_HZ} }}
  node {{ name: "cam" type: MOCK_CAMERA_PUBLISHER topic_name: "{IMAGE_TOPIC}" width: {WIDTH} height: {HEIGHT}
          rate_hz: {IMAGE_FPS} }}
"""
CHROMIUM = "/usr/bin/chromium-headless-shell"
CHROMIUM_FLAGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
WARMUP_S, QUICK_WARMUP_S = 3.0, 0.0
LEAVE_S, QUICK_LEAVE_S = 1.0, 0.0  # after a group of SSE clients stops, before the next connects
RUN_S, QUICK_RUN_S = 20.0, 1.0  # seconds per measurement; --quick only shows that every step works
SERVER_START_TIMEOUT_S = 60.0
POLL_S = 0.02
DOM_PROBE = """
window.__latency = {joints: [], image: []};
new MutationObserver((mutations) => {
  const now = Date.now();
  for (const m of mutations) {
    const el = m.target;
    if (m.type !== "attributes" || !el.dataset || !el.dataset.stampNs) continue;
    const kind = (el.dataset.testid || "").startsWith("camera-") ? "image" : "joints";
    window.__latency[kind].push(now - Number(BigInt(el.dataset.stampNs) / 1000000n));
  }
}).observe(document, {subtree: true, attributes: true, attributeFilter: ["data-stamp-ns"]});
"""


class Publisher:
    """Publishes the joint states and images from a thread, each stamped with time.time_ns()."""

    def __init__(self):
        import rclpy
        from sensor_msgs.msg import Image, JointState

        self.rclpy, self.Image, self.JointState = rclpy, Image, JointState
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node("bench_dashboard_publisher", context=self.context)
        from rclpy.qos import QoSProfile, ReliabilityPolicy

        # The mock nodes' default QoS: reliable joint states, best-effort camera frames.
        reliable = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
        best_effort = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)
        self.joints = self.node.create_publisher(JointState, JOINT_TOPIC, reliable)
        self.images = self.node.create_publisher(Image, IMAGE_TOPIC, best_effort)
        gradient = np.linspace(0, 255, WIDTH, dtype=np.uint8)
        self.frames = [
            np.ascontiguousarray(np.dstack([np.roll(gradient, 40 * i)[None, :].repeat(HEIGHT, 0)] * 3)).tobytes()
            for i in range(8)
        ]
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _stamp(self, message) -> None:
        now = time.time_ns()
        message.header.stamp.sec, message.header.stamp.nanosec = divmod(now, 1_000_000_000)

    def _run(self) -> None:
        start = time.monotonic()
        joint_n = image_n = 0
        while not self.stop.is_set():
            now = time.monotonic() - start
            if now >= joint_n / JOINT_HZ:
                t = joint_n / JOINT_HZ
                message = self.JointState(
                    name=JOINTS,
                    position=[np.sin(t + j) for j in range(6)],
                    velocity=[np.cos(t + j) for j in range(6)],
                    effort=[0.1 * j for j in range(6)],
                )
                self._stamp(message)
                self.joints.publish(message)
                joint_n += 1
            if now >= image_n / IMAGE_FPS:
                image = self.Image(
                    height=HEIGHT,
                    width=WIDTH,
                    encoding="rgb8",
                    step=WIDTH * 3,
                    data=self.frames[image_n % len(self.frames)],
                )
                self._stamp(image)
                self.images.publish(image)
                image_n += 1
            time.sleep(0.002)

    def close(self) -> None:
        self.stop.set()
        self.thread.join()
        self.node.destroy_node()
        self.rclpy.try_shutdown(context=self.context)


def server_cpu_percent(pid: int, seconds: float) -> float:
    before = cpu_seconds(pid)
    time.sleep(seconds)
    return 100.0 * (cpu_seconds(pid) - before) / seconds


def percentile(values, q) -> float:
    return float(np.percentile(values, q)) if values else float("nan")


class SseReader(threading.Thread):
    """A plain HTTP client of /api/events that counts events and notes joint latency (receive - stamp)."""

    def __init__(self, port: int, token: str):
        super().__init__(daemon=True)
        self.port, self.token, self.events, self.joint_latency_ms = port, token, 0, []
        self.stop = threading.Event()

    def run(self) -> None:
        connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=10)
        connection.request("GET", "/api/events", headers={"Authorization": f"Bearer {self.token}"})
        response = connection.getresponse()
        kind = ""
        while not self.stop.is_set():
            line = response.fp.readline()
            if not line:
                break
            if line.startswith(b"event: "):
                kind = line[7:].strip().decode()
            elif line.startswith(b"data: "):
                self.events += 1
                if kind == "joints":
                    start = line.index(b'"stamp_ns":') + 11
                    stamp = int(line[start : line.index(b",", start)])
                    self.joint_latency_ms.append((time.time_ns() - stamp) / 1e6)
        connection.close()


def measure_browser(port: int, token: str, seconds: float, warm_up_s: float) -> dict:
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        page = browser.new_page(viewport={"width": 1400, "height": 1000})
        page.add_init_script(DOM_PROBE)
        page.goto(f"http://127.0.0.1:{port}/#token={token}")
        page.wait_for_selector("[data-testid^='camera-']", timeout=30_000)
        time.sleep(warm_up_s)
        page.evaluate("window.__latency = {joints: [], image: []}")
        chromium = [pid for pid in descendants(os.getpid()) if runs_chromium(pid)]
        page_before, server_before = cpu_seconds_of(chromium), cpu_seconds(SERVER_PID[0])
        page.wait_for_timeout(seconds * 1000)
        page_cpu = 100.0 * (cpu_seconds_of(chromium) - page_before) / seconds
        server_cpu = 100.0 * (cpu_seconds(SERVER_PID[0]) - server_before) / seconds
        latency = page.evaluate("window.__latency")
        browser.close()
    return {"latency": latency, "server_cpu": server_cpu, "page_cpu": page_cpu}


SERVER_PID = [0]


def runs_chromium(pid: int) -> bool:
    """Whether process `pid` is one of Chromium's (browser, renderer, GPU, utility), not Playwright's driver."""
    try:
        program = os.readlink(f"/proc/{pid}/exe")  # Chromium rewrites its command line; its executable stays
    except OSError:
        return False
    return Path(program).name == Path(CHROMIUM).name


def stalled_client(port: int, token: str, pid: int, seconds: float) -> list[float]:
    """RSS samples (MiB) of the server, once a second, while one client never reads its stream."""
    sock = socket.create_connection(("127.0.0.1", port))
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.sendall(f"GET /api/events HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer {token}\r\n\r\n".encode())
    samples = []
    for _ in range(int(seconds)):
        time.sleep(1.0)
        samples.append(rss_mib(pid))
    sock.close()
    return samples


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="short runs, no warm-up (for the tests)")
    args = parser.parse_args()
    run_s = QUICK_RUN_S if args.quick else RUN_S
    warm_up_s, leave_s = (QUICK_WARMUP_S, QUICK_LEAVE_S) if args.quick else (WARMUP_S, LEAVE_S)
    with tempfile.TemporaryDirectory(prefix="bench-dashboard-") as directory:
        source = Path(directory) / "bench_dashboard.pbtxt"
        bridge_port = free_port()
        source.write_text(DESCRIPTION + foxglove_block(bridge_port) + "}\n")
        built = joshuac("build", source, "-o", Path(directory) / "out")
        if built.returncode != 0:
            raise SystemExit(built.stderr)
        out = Path(directory) / "out"
        os.environ.update(bench_environment("dashboard", FASTRTPS_DEFAULT_PROFILES_FILE=str(out / IMAGES_PROFILE_PATH)))
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
        server = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "joshua_runtime.dashboard",
                "--manifest",
                str(out / "manifest.json"),
                "--control-socket",
                str(Path(directory) / "none.sock"),
                "--port",
                str(port),
            ],
            stdout=subprocess.DEVNULL,
        )
        SERVER_PID[0] = server.pid
        publisher = Publisher()
        try:
            deadline = time.monotonic() + SERVER_START_TIMEOUT_S
            while True:
                try:
                    socket.create_connection(("127.0.0.1", port), timeout=1).close()
                    break
                except OSError:
                    if time.monotonic() > deadline or server.poll() is not None:
                        raise SystemExit("the dashboard server did not start") from None
                    time.sleep(0.2)
            time.sleep(warm_up_s)
            token = token_path(Path(directory) / "none.sock").read_text().strip()
            report(
                port,
                token,
                server.pid,
                (run_s, warm_up_s, leave_s),
                lambda: bridge_cpu_percent(out, bridge_port, TOPICS, run_s),
            )
        finally:
            publisher.close()
            server.terminate()
            server.wait(10)
    return 0


def report(port: int, token: str, pid: int, seconds: tuple[float, float, float], bridge) -> None:
    """The figures, each measured for `run_s` after `warm_up_s`, `leave_s` between groups of SSE clients."""
    run_s, warm_up_s, leave_s = seconds
    idle = server_cpu_percent(pid, run_s)
    print(
        f"publishing {JOINT_HZ:g} Hz JointState (6 joints) and {IMAGE_FPS:g} fps {WIDTH}x{HEIGHT} rgb8 Image; "
        f"{run_s:g} s per measurement"
    )
    print(f"server CPU with no client: {idle:.1f} %")

    browser = measure_browser(port, token, run_s, warm_up_s)
    for kind in ("joints", "image"):
        values = browser["latency"][kind]
        print(
            f"publish -> DOM latency, {kind:6s}: p50 {percentile(values, 50):6.1f} ms  p99 "
            f"{percentile(values, 99):6.1f} ms  ({len(values)} updates, {len(values) / run_s:.1f}/s)"
        )
    print(
        f"server CPU with 1 browser: {browser['server_cpu']:.1f} % "
        f"(+{browser['server_cpu'] - idle:.1f} % for the client); the page itself: Chromium's processes "
        f"{browser['page_cpu']:.1f} % of a core"
    )
    bridge_cpu, bridge_rates, bridge_latency = bridge()
    rates = ", ".join(f"{topic} {rate:.1f}/s" for topic, rate in bridge_rates.items())
    print(
        f"peer: the Foxglove bridge with 1 client taking both streams whole ({rates}): CPU {bridge_cpu:.1f} %; "
        f"dashboard with 1 browser / bridge: {browser['server_cpu'] / bridge_cpu:.2f}x"
    )
    for kind, topic in (("joints", JOINT_TOPIC), ("image", IMAGE_TOPIC)):
        values = bridge_latency[topic]
        print(
            f"peer: publish -> its client (Python, websockets), {kind:6s}: p50 {percentile(values, 50):6.1f} ms  "
            f"p99 {percentile(values, 99):6.1f} ms  ({len(values)} messages)"
        )

    for count in (1, 10):
        readers = [SseReader(port, token) for _ in range(count)]
        for reader in readers:
            reader.start()
        deadline = time.monotonic() + SERVER_START_TIMEOUT_S
        while not all(reader.events for reader in readers) and time.monotonic() < deadline:
            time.sleep(POLL_S)
        time.sleep(warm_up_s)
        for reader in readers:
            reader.events, reader.joint_latency_ms = 0, []
        cpu = server_cpu_percent(pid, run_s)
        for reader in readers:
            reader.stop.set()
        rates = [reader.events / run_s for reader in readers]
        latency = [v for reader in readers for v in reader.joint_latency_ms]
        print(
            f"{count:2d} SSE clients: server CPU {cpu:5.1f} % ({(cpu - idle) / count:.1f} % per client), "
            f"events/s per client min {min(rates):.1f} max {max(rates):.1f}, "
            f"joints latency p50 {percentile(latency, 50):.1f} ms p99 {percentile(latency, 99):.1f} ms"
        )
        time.sleep(leave_s)

    samples = stalled_client(port, token, pid, run_s * 2)
    print(
        f"stalled client for {len(samples)} s: server RSS {samples[0]:.1f} -> {samples[-1]:.1f} MiB "
        f"(max {max(samples):.1f}, growth over the second half {samples[-1] - samples[len(samples) // 2]:+.1f} MiB)"
    )


if __name__ == "__main__":
    sys.exit(main())
