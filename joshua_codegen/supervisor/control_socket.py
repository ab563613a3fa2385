"""Whose the control socket is: its private directory, its file bound there, and the peer credentials checked."""

import os
import socket
import stat

from joshua_codegen.supervisor.notify import UCRED

CONTROL_BACKLOG = 64  # connections the kernel queues before the supervisor accepts them
CONTROL_PROBE_TIMEOUT_S = 1.0  # how long a socket already at the path may take to accept a probe
SOCKET_PATH_MAX = 107  # bytes of a Unix socket address (sun_path, without its terminating NUL)
ANOTHER_PATH = "choose another path with --control-socket PATH (--no-control for none)"


class ControlSocketError(Exception):
    """Why the control socket cannot be served: one line."""


def control_name(robot: dict) -> str:
    """What names a supervisor's control socket: the robot, and on a robot of several hosts `<robot>.<host>`
    (one supervisor per host, and several may run on one computer)."""
    return f"{robot['name']}.{robot['host']}" if robot.get("host") else robot["name"]


def default_control_socket(robot: str) -> str:
    """$XDG_RUNTIME_DIR/joshua/<robot>.sock, else /tmp/joshua-<uid>/<robot>.sock (`robot`: a control_name)."""
    runtime_dir = os.environ.get("XDG_RUNTIME_DIR")
    directory = os.path.join(runtime_dir, "joshua") if runtime_dir else f"/tmp/joshua-{os.getuid()}"
    return os.path.join(directory, f"{robot}.sock")


def peer_credentials(connection: socket.socket) -> tuple[int, int, int]:
    """(pid, uid, gid) of the process at the other end of a connected Unix socket, as the kernel saw it
    when that process connected or listened (SO_PEERCRED)."""
    return UCRED.unpack(connection.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, UCRED.size))


def listener_gone(pid: int) -> bool:
    """Whether the process that listened on a socket (its SO_PEERCRED pid) has exited. A process it forked may
    still hold the listener a while (its guard before closing what it inherited, a node before its exec), and
    the kernel still takes connections for it, but nothing will ever accept them."""
    if pid <= 0:
        return False  # not known in this pid namespace
    try:
        with open(f"/proc/{pid}/stat") as stat_file:
            state = stat_file.read().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return True
    return state in ("Z", "X")


def may_control(uid: int) -> bool:
    """Whether a peer of `uid` may take part in this user's control socket: the same user, or root."""
    return uid in (os.geteuid(), 0)


def private_directory(directory: str) -> int:
    """An open descriptor of `directory` (created mode 0700 when missing); raises ControlSocketError unless it
    is a real directory (no symbolic link) of this user that no one else may enter or write in."""
    try:
        os.makedirs(os.path.dirname(os.path.abspath(directory)), exist_ok=True)
        os.mkdir(directory, 0o700)
    except FileExistsError:
        pass
    except OSError as exc:
        raise ControlSocketError(f"cannot create its directory {directory}: {exc.strerror or exc}") from None
    try:
        fd = os.open(directory, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC)
    except OSError as exc:
        what = "is a symbolic link or not a directory" if os.path.islink(directory) else (exc.strerror or str(exc))
        raise ControlSocketError(f"its directory {directory} {what}; remove it, or {ANOTHER_PATH}") from None
    info = os.fstat(fd)
    problem = None
    if info.st_uid != os.geteuid():
        problem = f"belongs to uid {info.st_uid}, not to uid {os.geteuid()}"
    elif stat.S_IMODE(info.st_mode) & 0o077:
        problem = (
            f"has mode {stat.S_IMODE(info.st_mode):04o}: others may rename or replace the socket in it "
            "(it must be 0700)"
        )
    if problem:
        os.close(fd)
        raise ControlSocketError(f"its directory {directory} {problem}; remove it, or {ANOTHER_PATH}")
    return fd


class SocketFile:
    """The control socket's file, in a private directory held open: bound and removed through that descriptor
    (/proc/self/fd/N/NAME), so a directory renamed or replaced meanwhile cannot redirect either."""

    def __init__(self, path: str):
        if len(os.fsencode(path)) > SOCKET_PATH_MAX:
            raise ControlSocketError(
                f"the path is longer than a Unix socket address holds ({SOCKET_PATH_MAX} bytes); {ANOTHER_PATH}"
            )
        self.path = path
        self.name = os.path.basename(path)
        self.directory = private_directory(os.path.dirname(path) or ".")
        self.address = f"/proc/self/fd/{self.directory}/{self.name}"  # the path, through the directory held
        self.inode = None  # of the socket bound here, so only that one is ever removed

    def bind(self) -> socket.socket:
        """A listening, non-blocking socket of mode 0600 at the path; a stale socket there is replaced. It is
        bound under a temporary name and linked to the path once it listens: a client that finds the path
        can connect."""
        self.clear_stale()
        listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM | socket.SOCK_CLOEXEC | socket.SOCK_NONBLOCK)
        temporary = f".{self.name}.{os.getpid()}"
        remove_quietly(temporary, self.directory)  # left by a killed supervisor of the same pid
        old_mask = os.umask(0o177)
        try:
            listener.bind(f"/proc/self/fd/{self.directory}/{temporary}")
            listener.listen(CONTROL_BACKLOG)
            os.link(temporary, self.name, src_dir_fd=self.directory, dst_dir_fd=self.directory)
        except FileExistsError:
            listener.close()
            raise ControlSocketError(f"another supervisor took it meanwhile; {ANOTHER_PATH}") from None
        except OSError as exc:
            listener.close()
            raise ControlSocketError(f"cannot bind it: {exc.strerror or exc}; {ANOTHER_PATH}") from None
        finally:
            os.umask(old_mask)
            remove_quietly(temporary, self.directory)
        self.inode = os.stat(self.name, dir_fd=self.directory, follow_symlinks=False).st_ino
        return listener

    def clear_stale(self) -> None:
        """Remove a socket left at the path by a supervisor that was killed (nobody listens, or only processes it
        forked still hold its listener); refuse anything else there."""
        try:
            info = os.stat(self.name, dir_fd=self.directory, follow_symlinks=False)
        except FileNotFoundError:
            return
        if not stat.S_ISSOCK(info.st_mode):
            raise ControlSocketError(f"{self.path} exists and is not a socket; remove it, or {ANOTHER_PATH}")
        probe = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM | socket.SOCK_CLOEXEC)
        probe.settimeout(CONTROL_PROBE_TIMEOUT_S)
        try:
            probe.connect(self.address)
            pid = peer_credentials(probe)[0]
        except ConnectionRefusedError:
            os.unlink(self.name, dir_fd=self.directory)  # nobody listens: left by a supervisor that was killed
            return
        except OSError as exc:  # a timeout too: a busy supervisor's queue is full
            raise ControlSocketError(f"{self.path} cannot be probed ({exc.strerror or exc}); {ANOTHER_PATH}") from None
        finally:
            probe.close()
        if listener_gone(pid):  # its supervisor was killed; what it had just forked still holds the listener
            os.unlink(self.name, dir_fd=self.directory)
            return
        raise ControlSocketError(f"another supervisor (pid {pid}) serves it; stop it, or {ANOTHER_PATH}")

    def remove(self) -> None:
        """Remove the socket file if it is still the one bound here; let go of the directory."""
        try:
            if (
                self.inode is not None
                and os.stat(self.name, dir_fd=self.directory, follow_symlinks=False).st_ino == self.inode
            ):
                os.unlink(self.name, dir_fd=self.directory)
        except OSError:
            pass
        os.close(self.directory)


def remove_quietly(name: str, directory: int) -> None:
    try:
        os.unlink(name, dir_fd=directory)
    except OSError:
        pass
