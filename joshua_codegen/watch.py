"""`joshuac run --watch`: rebuild when the description or a file it names changes, and reload the running robot.

The description and the files its processes read as they start (`Process.inputs`: calibration files, a URDF
or MJCF file, CUSTOM programs given by path) are looked at every WATCH_POLL_S, a stat(2) each: a change is a
new inode, size or modification time, so a file saved in place and one renamed over the old (as editors save)
are both seen, and so is a file that appears or goes. Once they have stayed the same for WATCH_SETTLE_S, the
description is built into a new directory beside the running build and `supervisor.py ctl reload` applies it:
the supervisor restarts what changed, starts what is new and stops what is gone (an input that changed restarts
the processes reading it, though the build is the same). A description with errors is reported with its
diagnostics and nothing is reloaded: the robot keeps running as it was.
"""

import shutil
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import click

from joshua_codegen.run import HostChoiceError
from joshua_codegen.supervisor.reload_plan import file_mark

WATCH_POLL_S = 0.05  # how often the watched files are looked at
WATCH_SETTLE_S = 0.1  # a change is built once the files stayed the same this long (a save may be several writes)
WATCH_SETTLE_MAX_S = 2.0  # files that keep changing are built after this long anyway


def watched_files(config: str, robot) -> list[str]:
    """The description and every file a process of `robot` reads as it starts, once each."""
    return list(dict.fromkeys([config, *(path for process in robot.processes for path in process.inputs)]))


class Watcher:
    """Follows a running supervisor for `joshuac run --watch`: `follow(process)` watches until it ends.

    `out` is the first build (its path is the prefix every rebuild keeps, so that unchanged files stay byte for
    byte the same) and `running` the directory of it whose supervisor.py runs; rebuilds go to `out-1`, `out-2`,
    ... beside it, the one before removed once the robot runs the new one. `run_directory(robot, built)` names
    the directory of a build whose supervisor.py runs here (`built` itself, or one host's part of it; raises
    HostChoiceError when the description has no such part any more)."""

    def __init__(self, config: str, overrides, out: Path, running: Path, robot, run_directory: Callable):
        self.config = config
        self.overrides = overrides
        self.out = out
        self.run_directory = run_directory
        self.supervisor = running / "supervisor.py"  # its `ctl` reaches the running supervisor
        self.current = out  # the build the robot runs
        self.rebuilds = 0
        self.marks = {path: file_mark(path) for path in watched_files(config, robot)}

    def follow(self, process: subprocess.Popen) -> int:
        """Watch and reload until the supervisor `process` exits; its exit status."""
        while process.poll() is None:
            time.sleep(WATCH_POLL_S)
            changed = self.changes()
            if changed:
                changed += self.settle()
                if process.poll() is None:
                    self.rebuild(list(dict.fromkeys(changed)))
        return process.wait()

    def changes(self) -> list[str]:
        """The watched files that changed since they were last looked at."""
        changed = []
        for path, mark in self.marks.items():
            now = file_mark(path)
            if now != mark:
                self.marks[path] = now
                changed.append(path)
        return changed

    def settle(self) -> list[str]:
        """Wait until the watched files stay the same for WATCH_SETTLE_S (WATCH_SETTLE_MAX_S at most); what
        changed meanwhile."""
        changed = []
        deadline = time.monotonic() + WATCH_SETTLE_MAX_S
        while time.monotonic() < deadline:
            time.sleep(WATCH_SETTLE_S)
            more = self.changes()
            if not more:
                break
            changed += more
        return changed

    def rebuild(self, changed: list[str]) -> None:
        from joshua_codegen.compile import compile_file
        from joshua_codegen.diagnostics import format_text, sort_diagnostics
        from joshua_codegen.write import OutputError, write_tree

        say(f"{', '.join(changed)} changed: rebuilding")
        compilation = compile_file(self.config, self.overrides, str(self.out))
        diagnostics = compilation.check.diagnostics
        if diagnostics:
            click.echo(format_text(sort_diagnostics(diagnostics), compilation.check.sources), err=True, nl=False)
        if compilation.files is None:
            say(f"{self.config} has errors: nothing reloaded, the robot keeps running as it was")
            return
        self.rebuilds += 1
        built = self.out.with_name(f"{self.out.name}-{self.rebuilds}")
        try:
            directory = self.run_directory(compilation.robot, built)
            write_tree(compilation.files, built)
        except (HostChoiceError, OutputError) as exc:
            say(f"error: {exc}: nothing reloaded")
            return
        reload = subprocess.run(  # supervisor.py is standard library only: -I -S spares the start-up of site
            [sys.executable, "-I", "-S", str(self.supervisor), "ctl", "reload", str(directory)],
            stdin=subprocess.DEVNULL,
            check=False,
        )
        if reload.returncode != 0:
            shutil.rmtree(built, ignore_errors=True)
            say("nothing reloaded: the robot keeps running as it was")
            return
        if self.current != self.out:
            shutil.rmtree(self.current, ignore_errors=True)
        self.current = built
        for path in watched_files(self.config, compilation.robot):
            self.marks.setdefault(path, file_mark(path))


def say(message: str) -> None:
    click.echo(f"joshuac: {message}", err=True)
