"""Act as another user on this machine (the tests run as root): a real other uid, nobody (65534).

`as_other_user(cwd, what, path)` runs a small program as that uid, with the working directory `cwd` (entered
while still root, so pytest's private directories need not be opened to it); `path` is relative to `cwd`:
- `dir777`: makes the directory of `path`, mode 0777;
- `prebind`: the same, then binds a Unix socket at `path`, prints "ready", and answers every connection
  with a fake status line, printing `got "<what it received>"`;
- `client`: connects to the socket at `path`, sends a status request and prints the reply lines
  ("EOF" at the end).
"""

import os
import subprocess
from pathlib import Path

OTHER_UID = OTHER_GID = 65534  # nobody
OTHER_PYTHON = "/usr/bin/python3"  # the system's: this environment's interpreter may live in root's home
OTHER_USER_PROGRAM = r"""
import json, os, socket, sys
what, path = sys.argv[1], sys.argv[2]
if what in ("dir777", "prebind"):
    os.mkdir(os.path.dirname(path))
    os.chmod(os.path.dirname(path), 0o777)
if what == "prebind":
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(path)
    os.chmod(path, 0o777)
    server.listen(8)
    print("ready", flush=True)
    while True:
        connection, _ = server.accept()
        print("got", json.dumps(connection.recv(4096).decode(errors="replace")), flush=True)
        connection.sendall(b'{"ok": true, "robot": "r", "nodes": []}\n')
        connection.close()
elif what == "client":
    client = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    client.settimeout(5)
    client.connect(path)
    try:
        client.sendall(b'{"command": "status"}\n')
    except BrokenPipeError:
        pass  # refused and closed before the request was sent: the reply says why
    replies = client.makefile("rb")
    for _ in range(2):
        try:
            line = replies.readline().decode().strip()
        except ConnectionResetError:  # closed with a request unread: the end as well
            line = ""
        print(line or "EOF", flush=True)
"""


def as_other_user(cwd: Path, what: str, path: str) -> subprocess.Popen:
    """OTHER_USER_PROGRAM doing `what` as uid OTHER_UID (checked), text stdout and stderr piped."""
    process = subprocess.Popen(
        [OTHER_PYTHON, "-I", "-S", "-c", OTHER_USER_PROGRAM, what, path],
        cwd=cwd,
        user=OTHER_UID,
        group=OTHER_GID,
        extra_groups=[],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    uids = next(
        line for line in Path(f"/proc/{process.pid}/status").read_text().splitlines() if line.startswith("Uid:")
    )
    assert uids.split()[1:] == [str(OTHER_UID)] * 4, uids
    assert os.getuid() != OTHER_UID
    return process
