"""The guard process: kills every node's process group when the supervisor dies without stopping them."""

import os
import signal

from joshua_codegen.supervisor.policy import STOP_SIGNALS


class Guard:
    """A forked helper that SIGKILLs every node's process group when the supervisor dies without
    stopping them (its pipe from the supervisor reaches end-of-file). Grandchildren that stayed in
    their node's group die with it; PR_SET_PDEATHSIG alone reaches only direct children."""

    def __init__(self):
        self.pid = None
        self.fd = None

    def start(self):
        read_end, self.fd = os.pipe()
        self.pid = os.fork()
        if self.pid == 0:
            os.close(self.fd)
            self.serve(read_end)
        os.close(read_end)

    @staticmethod
    def serve(read_end):
        code = 0
        try:
            os.setsid()
            for number in STOP_SIGNALS + (signal.SIGQUIT,):
                signal.signal(number, signal.SIG_IGN)
            groups, pending = set(), b""
            while True:
                data = os.read(read_end, 4096)
                if not data:
                    break
                pending += data
                *lines, pending = pending.split(b"\n")
                for line in lines:
                    (groups.add if line[:1] == b"+" else groups.discard)(int(line[1:]))
            for pgid in groups:
                try:
                    os.killpg(pgid, signal.SIGKILL)
                except OSError:
                    pass
        except BaseException:
            code = 1
        finally:
            os._exit(code)

    def send(self, line):
        if self.fd is not None:
            try:
                os.write(self.fd, line.encode())
            except OSError:
                self.fd = None

    def track(self, pgid):
        self.send(f"+{pgid}\n")

    def forget(self, pgid):
        self.send(f"-{pgid}\n")

    def stop(self):
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None
        if self.pid is not None:
            try:
                os.waitpid(self.pid, 0)
            except ChildProcessError:
                pass
            self.pid = None
