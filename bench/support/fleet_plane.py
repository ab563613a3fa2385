"""The fleet plane under a fleet's load: `joshua-fleet` (the Zenoh router and its page) and simulated robots,
each its own Zenoh session logging in with its own password (as robots do, README Security, Fleet), that
publish their status and one joint-state topic at 10 Hz as a robot's dashboard does.

Measured in one run: the server's CPU (utime+stime over the window, 100 % = one core) and RSS, idle (no
robot: the floor) and under the load; the latency from a status's put to `GET /api/robots` answering it
(every status of the probe robot, the API polled every 20 ms), and from a change of the probe's status
(every CHANGE_PERIOD_S) to the fleet page in headless Chromium showing it (a MutationObserver on the probe's
card). The page asks for /api/robots once a second (REFRESH_MS in web/src/fleet/main.tsx), so a change
waits half of that on average before any transport: the page latency's floor. And, under the same load, from
a robot's dashboard stopping (FleetLink.close(): it deletes its status key) to `GET /api/robots` listing that
robot offline, against the --offline-after (10 s) a robot that stops without a word takes.
"""

import json
import multiprocessing
import os
import secrets
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from dataclasses import dataclass
from pathlib import Path

from support.process_usage import cpu_seconds, rss_mib

ROOT = Path(__file__).resolve().parents[2]
RATE_HZ = 10.0
SESSIONS_PER_PROCESS = 10  # robots per publishing process (50 robots: 5 processes)
PAGE_REFRESH_S = 1.0  # web/src/fleet/main.tsx REFRESH_MS
API_POLL_S = 0.02
SERVER_START_TIMEOUT_S = 60.0
LINK_TIMEOUT_S = 60.0
PROBE = "bench_probe"  # the robot whose statuses carry their put time and its last change's, in its error text
LEAVER = "bench_leaver"  # the robot whose dashboard starts and stops, WITHDRAWALS times
WITHDRAWALS, QUICK_WITHDRAWALS = 20, 2
QUICK_PAGE_CHANGES = 2  # the first load and one change: one page latency
WITHDRAWAL_POLL_S = 0.002
OFFLINE_AFTER_S = 10.0  # joshua-fleet's default --offline-after: how long a silent robot still shows online
CHANGE_PERIOD_S = 1.3  # the probe's status changes this often (longer than the page's refresh: each change shows)
JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]
CHROMIUM = "/usr/bin/chromium-headless-shell"
DOM_PROBE = """
window.__shown = [];
new MutationObserver(() => {
  const card = document.querySelector('[data-testid="robot-bench_probe"]');
  const text = card ? card.textContent : "";
  const match = text.match(/changed at (\\d+)/);
  if (match && (window.__shown.length === 0 || window.__shown[window.__shown.length - 1][0] !== match[1])) {
    window.__shown.push([match[1], Date.now()]);
  }
}).observe(document, {subtree: true, childList: true, characterData: true});
"""


@dataclass(frozen=True)
class PlaneFigures:
    robots: int
    idle_cpu_percent: float
    cpu_percent: float
    idle_rss_mib: float
    rss_mib: float
    api_ms: tuple[float, float]  # p50, p99
    page_ms: tuple[float, float]
    statuses_per_s: float
    withdrawal_ms: tuple[float, float]

    def summary(self) -> str:
        return (
            f"fleet server, {self.robots} robots at {RATE_HZ:g} Hz (status + joints; {self.statuses_per_s:.0f} "
            f"statuses/s put): CPU {self.cpu_percent:.1f} % of a core (idle {self.idle_cpu_percent:.1f} %), "
            f"RSS {self.rss_mib:.1f} MiB (idle {self.idle_rss_mib:.1f} MiB, {self.rss_mib / self.idle_rss_mib:.2f}x)\n"
            f"status -> /api/robots p50 {self.api_ms[0]:.1f} ms, p99 {self.api_ms[1]:.1f} ms; "
            f"status change -> page p50 {self.page_ms[0]:.0f} ms, p99 {self.page_ms[1]:.0f} ms "
            f"({self.page_ms[0] / (PAGE_REFRESH_S * 500):.2f}x the {PAGE_REFRESH_S * 500:.0f} ms a change waits on "
            f"average for the page's {PAGE_REFRESH_S:g} s refresh)\n"
            f"dashboard stops -> /api/robots offline p50 {self.withdrawal_ms[0]:.1f} ms, p99 {self.withdrawal_ms[1]:.1f} "
            f"ms ({self.withdrawal_ms[0] / (OFFLINE_AFTER_S * 1000):.5f}x the {OFFLINE_AFTER_S:g} s of a silent robot)"
        )


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def robots_now(api: str) -> list:
    with urllib.request.urlopen(api, timeout=10) as answer:
        return json.loads(answer.read())


def status(robot: str, error: str | None = None) -> str:
    nodes = [{"name": n, "state": "running", "pid": 1000 + i, "restarts": 0, "ready": True, "since_s": 12.0}
             for i, n in enumerate(("leader", "follower", "camera", "dashboard"))]  # fmt: skip
    run = {"id": "0badcafe", "started": "2026-01-01T09:00:00.000+00:00", "build": "ab" * 32,
           "built": "2026-01-01T08:00:00.000+00:00"}  # fmt: skip
    return json.dumps({"robot": robot, "nodes": nodes, "run": run, "url": f"http://{robot}.lab:8640/", "error": error})


def joints(step: int) -> str:
    return json.dumps({"name": JOINTS, "position": [0.01 * step + j for j in range(6)], "velocity": [0.0] * 6})


def publish(endpoint: str, credentials: list[tuple[str, str]], seconds: float, linked, counter) -> None:
    """One process's robots: a session each, every one putting its status and joints at RATE_HZ."""
    import zenoh

    sessions = []
    for robot, password in credentials:
        config = zenoh.Config()
        for key, value in {"mode": "peer", "connect/endpoints": [endpoint], "listen/endpoints": [],
                           "scouting/multicast/enabled": False, "transport/auth/usrpwd/user": robot,
                           "transport/auth/usrpwd/password": password}.items():  # fmt: skip
            config.insert_json5(key, json.dumps(value))
        sessions.append((robot, zenoh.open(config)))
    deadline = time.monotonic() + LINK_TIMEOUT_S
    while not all(list(session.info.routers_zid()) for _, session in sessions):
        if time.monotonic() > deadline:
            raise RuntimeError("simulated robots did not link to the fleet")
        time.sleep(0.1)
    linked.release()
    period, step, started, changed_ms = 1.0 / RATE_HZ, 0, time.monotonic(), 0
    while time.monotonic() - started < seconds:
        for robot, session in sessions:
            now_ms = time.time_ns() // 1_000_000
            if now_ms - changed_ms >= CHANGE_PERIOD_S * 1000:
                changed_ms = now_ms
            error = f"changed at {changed_ms}, put at {now_ms}" if robot == PROBE else None
            session.put(f"joshua/{robot}/status", status(robot, error))
            session.put(f"joshua/{robot}/joints/leader/joint_states", joints(step))
        with counter.get_lock():
            counter.value += len(sessions)
        step += 1
        time.sleep(max(0.0, started + step * period - time.monotonic()))
    for _, session in sessions:
        session.close()


def percentile(values: list[float], fraction: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(fraction * len(ordered)))] if ordered else float("nan")


def robot_online(api: str, name: str) -> bool:
    return any(robot["name"] == name and robot["online"] for robot in robots_now(api))


def withdrawals(api: str, endpoint: str, leaver: tuple[str, str], times: int) -> list[float]:
    """Milliseconds from a dashboard's FleetLink closing to /api/robots listing its robot offline, `times` over."""
    from joshua_runtime.dashboard.zenoh_link import FleetLink, key_for

    robot, password = leaver
    settings = {"transport/auth/usrpwd/user": robot, "transport/auth/usrpwd/password": password}
    latencies = []
    for _ in range(times):
        link = FleetLink(robot, endpoint, "http://127.0.0.1:8640/", None, settings)
        deadline = time.monotonic() + LINK_TIMEOUT_S
        while not robot_online(api, robot):
            if time.monotonic() > deadline:
                raise RuntimeError(f"{robot} never showed online")
            link.put(key_for(robot, "status"), status(robot))
            time.sleep(API_POLL_S)
        started = time.monotonic()
        link.close()
        while robot_online(api, robot):
            time.sleep(WITHDRAWAL_POLL_S)
        latencies.append((time.monotonic() - started) * 1000)
    return latencies


def measure(robots: int, window_s: float, withdrawn: int = WITHDRAWALS, page_changes: int = 0) -> PlaneFigures:
    """The figures of `robots` over windows of `window_s` (the loaded one longer if need be, until the page
    showed `page_changes` of the probe's changes) and `withdrawn` withdrawals."""
    names = [PROBE] + [f"bench_robot_{i:02d}" for i in range(robots - 1)]
    credentials = [(name, secrets.token_urlsafe(18)) for name in names]
    leaver = (LEAVER, secrets.token_urlsafe(18))
    with tempfile.TemporaryDirectory(prefix="bench-fleet-") as work:
        users = Path(work, "users.txt")
        users.write_text("".join(f"{name}:{password}\n" for name, password in [*credentials, leaver]))
        users.chmod(0o600)
        endpoint, port = f"tcp/127.0.0.1:{free_port()}", free_port()
        server = subprocess.Popen(
            [sys.executable, "-m", "joshua_runtime.dashboard.fleet", "--listen", endpoint, "--port", str(port),
             "--users", str(users), "--rollout-state", os.devnull],
            stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT, cwd=ROOT,
        )  # fmt: skip
        api = f"http://127.0.0.1:{port}/api/robots"
        try:
            deadline = time.monotonic() + SERVER_START_TIMEOUT_S
            while True:
                try:
                    robots_now(api)
                    break
                except OSError:
                    if server.poll() is not None or time.monotonic() > deadline:
                        raise RuntimeError("joshua-fleet did not start") from None
                    time.sleep(0.2)
            idle_cpu, idle_rss = cpu_window(server.pid, window_s), rss_mib(server.pid)
            return loaded(
                server.pid, api, f"http://127.0.0.1:{port}/", endpoint, credentials, window_s, idle_cpu, idle_rss,
                lambda: withdrawals(api, endpoint, leaver, withdrawn), page_changes,
            )  # fmt: skip
        finally:
            server.terminate()
            server.wait(10)


def shown_now(page) -> list:
    """The probe's changes the page has shown so far: [changed at (ms), shown at (ms)]."""
    return page.evaluate("window.__shown")


def cpu_window(pid: int, seconds: float) -> float:
    before, started = cpu_seconds(pid), time.monotonic()
    time.sleep(seconds)
    return 100.0 * (cpu_seconds(pid) - before) / (time.monotonic() - started)


def loaded(
    pid, api, page_url, endpoint, credentials, window_s, idle_cpu, idle_rss, withdraw, page_changes
) -> PlaneFigures:
    from playwright.sync_api import sync_playwright

    groups = [credentials[i : i + SESSIONS_PER_PROCESS] for i in range(0, len(credentials), SESSIONS_PER_PROCESS)]
    linked, counter = multiprocessing.Semaphore(0), multiprocessing.Value("l", 0)
    seconds = window_s * 2 + LINK_TIMEOUT_S
    workers = [
        multiprocessing.Process(target=publish, args=(endpoint, group, seconds, linked, counter)) for group in groups
    ]
    for worker in workers:
        worker.start()
    try:
        for _ in workers:
            if not linked.acquire(timeout=LINK_TIMEOUT_S):
                raise RuntimeError("simulated robots did not link to the fleet")
        while len(robots_now(api)) < len(credentials):
            time.sleep(0.1)
        with sync_playwright() as playwright:
            chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"])
            page = chromium.new_page()
            page.add_init_script(DOM_PROBE)
            page.goto(page_url)
            cpu_before, started, put_before = cpu_seconds(pid), time.monotonic(), counter.value
            api_latencies, seen = [], set()
            while time.monotonic() - started < window_s or (page_changes and len(shown_now(page)) < page_changes):
                if time.monotonic() - started > window_s + LINK_TIMEOUT_S:
                    raise RuntimeError(f"the fleet page showed fewer than {page_changes} changes of {PROBE}")
                for robot in robots_now(api):
                    error = robot.get("error") or ""
                    if robot["name"] == PROBE and "put at " in error and error not in seen:
                        seen.add(error)
                        api_latencies.append(time.time_ns() / 1e6 - int(error.split()[-1]))
                time.sleep(API_POLL_S)
            elapsed = time.monotonic() - started
            cpu = 100.0 * (cpu_seconds(pid) - cpu_before) / elapsed
            statuses_per_s = (counter.value - put_before) / elapsed
            rss = rss_mib(pid)
            shown = shown_now(page)
            chromium.close()
        withdrawn = withdraw()  # while the robots still publish
        page_latencies = [shown_at - int(put_at) for put_at, shown_at in shown[1:]]  # the first load aside
        return PlaneFigures(
            robots=len(credentials),
            idle_cpu_percent=idle_cpu,
            cpu_percent=cpu,
            idle_rss_mib=idle_rss,
            rss_mib=rss,
            api_ms=(percentile(api_latencies, 0.5), percentile(api_latencies, 0.99)),
            page_ms=(percentile(page_latencies, 0.5), percentile(page_latencies, 0.99)),
            statuses_per_s=statuses_per_s,
            withdrawal_ms=(percentile(withdrawn, 0.5), percentile(withdrawn, 0.99)),
        )
    finally:
        for worker in workers:
            worker.terminate()
            worker.join(10)
