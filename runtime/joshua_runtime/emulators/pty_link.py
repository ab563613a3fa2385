"""A raw pseudo-terminal exposed at a symlink path, the way a USB serial adapter appears."""

import array
import fcntl
import os
import termios
import tty
from pathlib import Path

TCGETS2 = 0x802C542A  # _IOR('T', 0x2A, struct termios2): reads arbitrary (BOTHER) speeds too
TERMIOS2_INTS = 16  # struct termios2 is 44 bytes; 64 leaves room
TERMIOS2_OSPEED_INDEX = 10  # 4 flag words, c_line + 19 c_cc bytes (36 bytes), c_ispeed, c_ospeed


class PtyLink:
    """Owns a pty master; the slave side is reachable at `link` (e.g. /tmp/ttyEMU0).

    The emulator reads requests from and writes replies to `master_fd`. Closing removes the link.
    """

    def __init__(self, link: str | os.PathLike):
        self.link = Path(link)
        self.master_fd, self._slave_fd = os.openpty()
        tty.setraw(self._slave_fd, termios.TCSANOW)
        self.slave_name = os.ttyname(self._slave_fd)
        if self.link.is_symlink() or self.link.exists():
            self.link.unlink()
        self.link.symlink_to(self.slave_name)

    def line_speed(self) -> int | None:
        """The baud rate the program on the slave side set, as a UART would be clocked."""
        return line_speed(self.master_fd)

    def close(self) -> None:
        if self.link.is_symlink() and os.readlink(self.link) == self.slave_name:
            self.link.unlink()
        for fd in (self.master_fd, self._slave_fd):
            try:
                os.close(fd)
            except OSError:
                pass

    def __enter__(self) -> "PtyLink":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def line_speed(fd: int) -> int | None:
    """The baud rate the other side configured on the pty (Linux TCGETS2), or None if unreadable."""
    buffer = array.array("i", [0] * TERMIOS2_INTS)
    try:
        fcntl.ioctl(fd, TCGETS2, buffer)
    except OSError:
        return None
    return buffer[TERMIOS2_OSPEED_INDEX] or None
