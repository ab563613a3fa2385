"""After a crash, the Discovery Server starts again only once its clients have dropped the crashed one.

A server killed without stopping (SIGKILL, a crash, a power cut of its process) is dropped by its
clients only when its lease runs out. Started again before that, it has the same GUID and meets
clients that keep the old server's reliable-discovery state: they may never learn of an endpoint
announced after the restart (docs/multihost-dds.md). So while the server serves, its launcher touches a
heartbeat file on its host every HEARTBEAT_S, removes it when the server ended as asked, and a launcher
that finds one left behind waits until twice the lease has passed since its last touch. The file lives
in /dev/shm: on the server's own host, gone after a reboot, and private to each simulated host.
"""

import xml.etree.ElementTree as ElementTree
from pathlib import Path

HEARTBEAT_DIR = Path("/dev/shm")
HEARTBEAT_S = 1.0  # how often a running server's launcher touches its heartbeat file
DEFAULT_LEASE_S = 20.0  # Fast DDS's participant lease when a profile names none
LEASES_TO_WAIT = 2  # the tested remedy: start again no sooner than twice the lease after the crash
DDS_NAMESPACE = "{http://www.eprosima.com}"


def heartbeat_path(address: str, port: int, directory: Path = HEARTBEAT_DIR) -> Path:
    return directory / f"joshua-discovery-server-{address}-{port}.heartbeat"


def lease_s(profile: str) -> float:
    """The participant lease a server profile sets (DEFAULT_LEASE_S without one); ValueError when unreadable."""
    if not profile:
        return DEFAULT_LEASE_S
    try:
        lease = ElementTree.parse(profile).find(f".//{DDS_NAMESPACE}leaseDuration")
    except ElementTree.ParseError as exc:
        raise ValueError(f"the server profile {profile} is not XML: {exc}") from None
    if lease is None:
        return DEFAULT_LEASE_S
    seconds = lease.findtext(f"{DDS_NAMESPACE}sec", "0").strip()
    nanoseconds = lease.findtext(f"{DDS_NAMESPACE}nanosec", "0").strip()
    try:
        return int(seconds) + int(nanoseconds) / 1e9
    except ValueError:
        raise ValueError(f"the server profile {profile} has a lease of {seconds!r} s {nanoseconds!r} ns") from None


def pause_needed_s(heartbeat: Path, lease: float, now: float) -> float:
    """How long to wait before starting: 0 unless a crashed server's heartbeat is younger than its clients' patience."""
    try:
        last_beat = heartbeat.stat().st_mtime
    except FileNotFoundError:
        return 0.0
    return max(0.0, last_beat + HEARTBEAT_S + LEASES_TO_WAIT * lease - now)


def beat(heartbeat: Path) -> None:
    """Mark the server alive now; a heartbeat that cannot be written only costs the pause, never the server."""
    try:
        heartbeat.touch()
    except OSError:
        pass


def clear(heartbeat: Path) -> None:
    """The server ended as asked (it told its clients it leaves): a next start need not wait."""
    try:
        heartbeat.unlink(missing_ok=True)
    except OSError:
        pass
