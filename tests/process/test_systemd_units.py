"""The systemd units: `systemd-analyze verify` accepts every one, and they map the cascade and restarts."""

import re
import subprocess
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from supervisor_harness import PYTHON, build, custom_node, quoted, robot

from joshua_codegen.compile import compile_file
from joshua_codegen.escape import systemd_command, systemd_quote
from joshua_core.exit_codes import NODE_EXIT_SETTINGS

SYSTEMD_ANALYZE = "/usr/bin/systemd-analyze"
ROOT = Path(__file__).resolve().parents[2]
SEEDS = sorted((ROOT / "config" / "robots").glob("*.pbtxt"))
NASTY = [
    "$HOME",
    "${HOME}",
    "%h",
    "%%",
    "it's",
    'say "hi"',
    "back\\slash",
    "a ;b",
    ";",
    "tab\there",
    "new\nline",
    "",
    " lead",
    "trail ",
    "\\n",
    "\x7f",
    "é✓",
]


def verify(out: Path) -> subprocess.CompletedProcess:
    units = sorted(str(path) for path in (out / "systemd").iterdir())
    assert units
    return subprocess.run([SYSTEMD_ANALYZE, "verify", *units], capture_output=True, text=True, cwd=out)


def build_units(config: Path) -> dict[str, str]:
    files = compile_file(str(config)).files
    return {path: text for path, text in files.items() if path.startswith("systemd/")}


def settings_of(text: str) -> list[tuple[str, str]]:
    return [tuple(line.split("=", 1)) for line in text.splitlines() if re.match(r"^[A-Za-z]+=", line)]


def unquote(line: str, exec_line: bool = True) -> list[str]:
    """Split an Exec*= or Environment= value the way systemd documents it (quotes, C escapes, %%, $$)."""
    words, i = [], 0
    escapes = {"n": "\n", "t": "\t", "r": "\r", "\\": "\\", '"': '"', "'": "'"}
    while i < len(line):
        if line[i] == " ":
            i += 1
            continue
        word = []
        if line[i] == '"':
            i += 1
            while line[i] != '"':
                if line[i] == "\\":
                    if line[i + 1] == "x":
                        word.append(chr(int(line[i + 2 : i + 4], 16)))
                        i += 4
                        continue
                    word.append(escapes[line[i + 1]])
                    i += 2
                    continue
                word.append(line[i])
                i += 1
            i += 1
        else:
            while i < len(line) and line[i] != " ":
                word.append(line[i])
                i += 1
        text = "".join(word).replace("%%", "%")
        words.append(text.replace("$$", "$") if exec_line else text)
    return words


@pytest.mark.parametrize("config", SEEDS, ids=lambda p: p.stem)
def test_units_of_every_seed_description_pass_systemd_analyze_verify(config, tmp_path):
    out = build(tmp_path, config.read_text(), source=config.name, prefix=str(tmp_path / "out"))
    result = verify(out)
    assert (result.returncode, result.stderr, result.stdout) == (0, "", "")


def test_units_with_odd_values_pass_verify_and_keep_every_value(tmp_path):
    log = tmp_path / "events.log"
    env = " ".join(f"env {{ key: {quoted(f'V{i}')} value: {quoted(v)} }}" for i, v in enumerate(NASTY))
    env += ' env { key: "DASH-KEY" value: "d e" }'
    node = custom_node("odd", log, *NASTY)[:-1] + f" {env} }}"
    out = build(tmp_path, robot([node]), prefix=str(tmp_path / "out"))
    result = verify(out)
    assert (result.returncode, result.stderr) == (0, "")
    unit = dict(settings_of((out / "systemd" / "joshua-r-odd.service").read_text()))
    assert unquote(unit["ExecStart"])[:3] == ["/usr/bin/env", "DASH-KEY=d e", PYTHON]  # not a valid Environment= key
    assert unquote(unit["ExecStart"])[-len(NASTY) :] == NASTY
    text = (out / "systemd" / "joshua-r-odd.service").read_text()
    environment = [unquote(value, exec_line=False)[0] for key, value in settings_of(text) if key == "Environment"]
    assert dict(item.split("=", 1) for item in environment[-len(NASTY) :]) == {f"V{i}": v for i, v in enumerate(NASTY)}


@settings(max_examples=200, deadline=None)
@given(
    st.lists(
        st.text(
            alphabet=st.characters(codec="utf-8", exclude_characters="\0", exclude_categories=("Cs",)), max_size=20
        ),
        min_size=1,
        max_size=4,
    )
)
def test_systemd_quoting_round_trips(words):
    assert unquote(" ".join(systemd_quote(w) for w in words)) == words


def test_odd_program_paths_run_through_sh_which_systemd_accepts(tmp_path):
    program = tmp_path / "my tool's $dir" / "run"
    program.parent.mkdir()
    program.write_text("#!/bin/sh\n")
    program.chmod(0o755)
    line = systemd_command([str(program), "x"])
    assert unquote(line) == ["/bin/sh", "-c", 'exec "$0" "$@"', str(program), "x"]
    unit = tmp_path / "odd.service"
    unit.write_text(f"[Unit]\nDescription=odd\n[Service]\nExecStart={line}\n")
    result = subprocess.run([SYSTEMD_ANALYZE, "verify", str(unit)], capture_output=True, text=True)
    assert (result.returncode, result.stderr) == (0, "")


def test_units_map_the_cascade_restarts_and_criticality(tmp_path):
    log = tmp_path / "events.log"
    nodes = [
        custom_node("main", log, max_restarts="3"),
        custom_node("helper", log, restart="RESTART_ALWAYS", critical="false"),
        custom_node("once", log, restart="RESTART_NEVER"),
    ]
    out = build(tmp_path, robot(nodes, sigint=0.3, sigterm=2, extra="ros_domain_id: 9"), prefix="/srv/joshua/r")
    units = out / "systemd"
    assert sorted(p.name for p in units.iterdir()) == [
        "joshua-r-helper.service",
        "joshua-r-main.service",
        "joshua-r-once.service",
        "joshua-r.target",
    ]
    target = settings_of((units / "joshua-r.target").read_text())
    assert [s for s in target if s[0] in ("BindsTo", "Wants")] == [
        ("BindsTo", "joshua-r-main.service"),
        ("BindsTo", "joshua-r-once.service"),
        ("Wants", "joshua-r-helper.service"),
    ]
    main = settings_of((units / "joshua-r-main.service").read_text())
    assert [
        s
        for s in main
        if s[0]
        in (
            "KillMode",
            "KillSignal",
            "TimeoutStopSec",
            "TimeoutStopFailureMode",
            "WatchdogSignal",
            "TimeoutAbortSec",
            "FinalKillSignal",
            "SendSIGKILL",
        )
    ] == [
        ("KillMode", "control-group"),
        ("KillSignal", "SIGINT"),
        ("TimeoutStopSec", "300ms"),
        ("TimeoutStopFailureMode", "abort"),
        ("WatchdogSignal", "SIGTERM"),
        ("TimeoutAbortSec", "2s"),
        ("FinalKillSignal", "SIGKILL"),
        ("SendSIGKILL", "yes"),
    ]
    main = dict(main)
    assert (main["Restart"], main["RestartSec"], main["StartLimitBurst"], main["StartLimitIntervalSec"]) == (
        "on-failure",
        "250ms",
        "4",
        "240s",
    )
    assert (main["PartOf"], main["WantedBy"], main["WorkingDirectory"]) == (
        "joshua-r.target",
        "joshua-r.target",
        "/srv/joshua/r",
    )
    assert unquote(main["ExecStart"])[:4] == [PYTHON, "-I", "-S", str(tmp_path / "behave.py")]
    environment = [
        value for key, value in settings_of((units / "joshua-r-main.service").read_text()) if key == "Environment"
    ]
    assert environment == [
        "FASTRTPS_DEFAULT_PROFILES_FILE=/srv/joshua/r/fastdds_profile_images.xml",
        "PYTHONUNBUFFERED=1",
        "ROS_DOMAIN_ID=9",
    ]
    helper = dict(settings_of((units / "joshua-r-helper.service").read_text()))
    once = dict(settings_of((units / "joshua-r-once.service").read_text()))
    assert (helper["Restart"], "RemainAfterExit" in helper) == ("always", False)
    assert (once["Restart"], once["RemainAfterExit"], "RestartSec" in once) == ("no", "yes", False)
    assert "RestartPreventExitStatus" not in main  # a CUSTOM program's exit 2 means what it means to it


def test_a_node_with_unusable_settings_is_not_restarted_by_systemd():
    units = build_units(ROOT / "config" / "robots" / "so100_leader_follower.pbtxt")
    for name, text in units.items():
        if name.endswith(".service"):
            assert dict(settings_of(text))["RestartPreventExitStatus"] == str(NODE_EXIT_SETTINGS), name


def test_python_nodes_run_through_env_and_cpp_nodes_through_a_fallback_script(tmp_path):
    config = (ROOT / "config" / "robots" / "so100_leader_follower.pbtxt").read_text()
    out = build(tmp_path, config, prefix="/opt/joshua/so100")
    units = out / "systemd"
    recorder = dict(settings_of(next(units.glob("*-data_subscriber.service")).read_text()))
    assert unquote(recorder["ExecStart"]) == ["/usr/bin/env", "python3", "/opt/joshua/so100/nodes/data_subscriber.py"]
    encoder = dict(settings_of(next(units.glob("*-encoder_publisher.service")).read_text()))
    sh, flag, script = unquote(encoder["ExecStart"])
    assert (sh, flag) == ("/bin/sh", "-c")
    assert script.startswith(
        "if [ -f /opt/joshua/bin/encoder_publisher ] && [ -x /opt/joshua/bin/encoder_publisher ]; "
        "then exec /opt/joshua/bin/encoder_publisher --ros-args -r __node:=encoder_publisher "
    )
    assert script.endswith("exec /usr/bin/env python3 /opt/joshua/so100/nodes/encoder_publisher.py")


def test_runtime_nodes_notify_readiness_and_feed_a_watchdog_while_others_start_as_exec(tmp_path):
    config = (ROOT / "config" / "robots" / "so100_leader_follower.pbtxt").read_text()
    config = config.replace(
        "robot_config {", 'robot_config {\n  node { name: "tool" type: CUSTOM executable: "/bin/true" }', 1
    )
    out = build(tmp_path, config)
    units = {
        path.name.split("-", 2)[2].removesuffix(".service"): dict(settings_of(path.read_text()))
        for path in (out / "systemd").glob("*.service")
    }
    recorder, encoder, tool = units["data_subscriber"], units["encoder_publisher"], units["tool"]
    for unit in (recorder, encoder):  # the Python runtime and the C++ binaries speak sd_notify
        assert (unit["Type"], unit["NotifyAccess"], unit["WatchdogSec"]) == ("notify", "main", "20s")
    assert recorder["TimeoutStartSec"] == "90s"
    # a CUSTOM program need not speak sd_notify
    assert tool["Type"] == "exec" and "NotifyAccess" not in tool and "WatchdogSec" not in tool
    assert verify(out).returncode == 0, verify(out).stderr
