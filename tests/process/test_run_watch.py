"""`joshuac run CFG --watch`: a saved description is rebuilt and applied to the running robot; only what changed
restarts, a description with errors is reported and changes nothing, a changed program file restarts its node."""

import os
import re
import signal
import subprocess
import sys

from supervisor_harness import WAIT_S, custom_node, events, robot, wait_until

RUN_TIMEOUT_S = 30.0


class WatchedRun:
    """`joshuac run CONFIG --watch` in `directory`, its output (stdout and stderr) kept in a file."""

    def __init__(self, directory, config, *options: str):
        self.output_path = directory / "joshuac.out"
        self.output = open(self.output_path, "w")
        self.process = subprocess.Popen(
            [sys.executable, "-m", "joshua_codegen", "run", str(config), "--watch", *options],
            cwd=directory,
            stdout=self.output,
            stderr=subprocess.STDOUT,
        )

    def text(self) -> str:
        return self.output_path.read_text()

    def wait_for(self, pattern: str, after: int = 0) -> int:
        """Wait until `pattern` shows in the output after offset `after`; where its match ends."""
        match = wait_until(lambda: re.compile(pattern, re.M).search(self.text(), after), f"{pattern!r} from joshuac")
        return match.end()

    def stop(self) -> int:
        self.process.send_signal(signal.SIGINT)
        try:
            return self.process.wait(RUN_TIMEOUT_S)
        finally:
            self.process.kill()
            self.output.close()


def save(path, text: str) -> None:
    """Save as editors do: a new file renamed over the old one."""
    temporary = path.with_name(path.name + ".swp")
    temporary.write_text(text)
    os.replace(temporary, path)


def history(log) -> dict[str, list[tuple[int, str]]]:
    by_node: dict[str, list[tuple[int, str]]] = {}
    for name, pid, text in events(log):
        by_node.setdefault(name, []).append((pid, text))
    return by_node


def test_a_saved_description_restarts_only_what_changed_and_one_with_errors_changes_nothing(tmp_path):
    log = tmp_path / "events.log"
    config = tmp_path / "r.pbtxt"
    config.write_text(robot([custom_node("steady", log), custom_node("tuned", log)]))
    run = WatchedRun(tmp_path, config)
    try:
        seen = run.wait_for(r"supervisor: ready: 2 of 2 nodes ready")
        wait_until(lambda: len(events(log)) == 2, "both nodes to start")
        first = {name: pid for name, pid, _ in events(log)}

        save(config, robot([custom_node("steady", log), custom_node("tuned", log, "exit_after=3600")]))
        seen = run.wait_for(r"^restarted tuned \(command line\)\nunchanged: steady$", seen)
        wait_until(lambda: len(history(log)["tuned"]) == 3, "the new tuned to start")
        tuned = history(log)["tuned"]
        assert tuned[:2] == [(first["tuned"], "start"), (first["tuned"], "got SIGINT exit")]
        assert tuned[2][0] != first["tuned"] and tuned[2][1] == "start"
        assert history(log)["steady"] == [(first["steady"], "start")]

        broken = robot([custom_node("steady", log), custom_node("tuned", log)]).replace("name:", "nme:", 1)
        save(config, broken)
        seen = run.wait_for(
            r"joshuac: .*r\.pbtxt has errors: nothing reloaded, the robot keeps running as it was", seen
        )
        assert re.search(r'r\.pbtxt:1:\d+: error\[E\d+\]: unknown field "nme"', run.text())

        other = robot([custom_node("steady", log), custom_node("tuned", log)]).replace('name: "r"', 'name: "r2"', 1)
        save(config, other)
        seen = run.wait_for(r"cannot reload .*: a build of robot 'r2', not of robot 'r'\n", seen)
        run.wait_for(r"nothing reloaded: the robot keeps running as it was", seen)

        save(
            config,
            robot(
                [custom_node("steady", log), custom_node("tuned", log, "exit_after=3600"), custom_node("added", log)]
            ),
        )
        run.wait_for(r"^started added\nunchanged: steady, tuned$", seen)
        wait_until(lambda: "added" in history(log), "the added node to start")
        assert history(log)["steady"] == [(first["steady"], "start")]
        assert history(log)["tuned"] == tuned  # neither the description with errors nor the other robot touched it
    finally:
        code = run.stop()
    assert code == 0, run.text()[-3000:]
    assert "Traceback" not in run.text()


def test_a_changed_program_file_restarts_the_node_running_it(tmp_path):
    log = tmp_path / "events.log"
    program = tmp_path / "tool.sh"
    script = "#!/bin/sh\necho tool $$ {word} >> {log}\ntrap 'exit 0' INT TERM\nwhile :; do sleep 0.05; done\n"
    program.write_text(script.format(word="first", log=log))
    program.chmod(0o755)
    config = tmp_path / "r.pbtxt"
    config.write_text(
        robot([custom_node("steady", log), f'node {{ name: "tool" type: CUSTOM executable: "{program}" }}'])
    )
    run = WatchedRun(tmp_path, config)
    try:
        seen = run.wait_for(r"supervisor: ready: 2 of 2 nodes ready")
        save(program, script.format(word="second", log=log))
        program.chmod(0o755)
        run.wait_for(rf"^restarted tool \({re.escape(str(program))} changed\)\nunchanged: steady$", seen)
        wait_until(lambda: any(text == "second" for _, text in history(log)["tool"]), "the new program to run", WAIT_S)
        # "ready" counts a CUSTOM node once exec'd, before its program wrote its line
        wait_until(lambda: "steady" in history(log), "the steady node's start line", WAIT_S)
        assert [text for _, text in history(log)["steady"]] == ["start"]
    finally:
        code = run.stop()
    assert code == 0, run.text()[-3000:]


def test_one_host_reloads_its_own_part_only(tmp_path):
    log = tmp_path / "events.log"
    hosts = 'host { name: "arm" address: "127.0.0.1" } host { name: "station" address: "127.0.0.2" }'

    def description(arm_options=(), station_options=()):
        arm = custom_node("a", log, *arm_options, host='"arm"')
        station = custom_node("b", log, *station_options, host='"station"')
        return robot([arm, station], extra=hosts)

    config = tmp_path / "r.pbtxt"
    config.write_text(description())
    run = WatchedRun(tmp_path, config, "--host", "arm")
    try:
        seen = run.wait_for(r"supervisor: ready: 2 of 2 nodes ready")  # a, and the host's agent
        wait_until(lambda: "a" in history(log), "a to start")
        save(config, description(station_options=("exit_after=3600",)))
        seen = run.wait_for(r"^reloaded robot r: .*\nunchanged: a, host_agent_arm$", seen)
        save(config, description(arm_options=("exit_after=3600",)))
        run.wait_for(r"^restarted a \(command line\)\nunchanged: host_agent_arm$", seen)
        wait_until(lambda: len(history(log)["a"]) == 3, "the new a to start")
        assert "b" not in history(log)  # the station's node runs on its own host's supervisor
    finally:
        code = run.stop()
    assert code == 0, run.text()[-3000:]
