"""Fast DDS shared-memory files a dead node left in /dev/shm, found by their free lock and removed."""

import os

SHM_DIR = "/dev/shm"
PROC_LOCKS = "/proc/locks"
# Fast DDS (2.x, as in ROS 2 Jazzy) names every segment `fastrtps_<random id>` or `fastrtps_port<N>`
# and holds an exclusive flock on `<segment>_el` for as long as the segment is in use (taken before the
# segment is created); a port also has the POSIX semaphore `sem.<segment>_mutex`.
FASTDDS_PREFIX = "fastrtps_"
LOCK_SUFFIX = "_el"
COMPANIONS = ("{}", "sem.{}_mutex", "{}_el")  # the lock file last: while it exists, the set is findable


def locked_inodes(device: int) -> set[int]:
    """Inodes on `device` that some live process holds a lock on (from /proc/locks)."""
    wanted = f"{os.major(device):02x}:{os.minor(device):02x}:"
    inodes = set()
    try:
        with open(PROC_LOCKS) as locks:
            for line in locks:
                for field in line.split():
                    if field.startswith(wanted):
                        inodes.add(int(field[len(wanted) :]))
    except OSError:
        pass
    return inodes


def abandoned_segments(since: float) -> list[str]:
    """Segments whose lock file was created at or after wall-clock time `since` and is held by no live
    process: their owner is dead (a live owner holds the lock before the segment even exists)."""
    try:
        device = os.stat(SHM_DIR).st_dev
        names = os.listdir(SHM_DIR)
    except OSError:
        return []
    locked = locked_inodes(device)
    found = []
    for name in sorted(names):
        if not (name.startswith(FASTDDS_PREFIX) and name.endswith(LOCK_SUFFIX)):
            continue
        try:
            lock = os.stat(os.path.join(SHM_DIR, name))
        except OSError:
            continue
        segment = name[: -len(LOCK_SUFFIX)]
        if lock.st_ino not in locked and lock.st_ctime >= since and os.path.exists(os.path.join(SHM_DIR, segment)):
            found.append(segment)
    return found


def remove_abandoned_segments(since: float) -> tuple[int, int]:
    """Remove the files of every abandoned segment created since `since`: (files removed, bytes freed)."""
    files = size = 0
    for segment in abandoned_segments(since):
        for pattern in COMPANIONS:
            path = os.path.join(SHM_DIR, pattern.format(segment))
            try:
                length = os.stat(path).st_size
                os.unlink(path)
            except OSError:
                continue
            files += 1
            size += length
    return files, size
