"""A raw pseudo-terminal exposed at a symlink path, the way a USB serial adapter appears."""

import os
import termios
import tty
from pathlib import Path


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
