"""A robot on several hosts: one complete output per host, placement in the manifest, DDS discovery through the
server, JPEG copies of images that cross hosts, and nothing of one host in another's output."""

import json
import re
import shutil
import subprocess

import pytest

from joshua_codegen.check import check_text
from joshua_codegen.diagnostics import format_text
from joshua_codegen.emitters.supervisor import supervisor_data
from joshua_codegen.plan import plan
from joshua_codegen.render import render
from joshua_core.feature_keys import image_key
from testsupport.joshuac_cli import joshuac

SYSTEMD_ANALYZE = "/usr/bin/systemd-analyze"
HOSTS = """
  host { name: "arm" address: "10.0.0.2" }
  host { name: "gpu" address: "10.0.0.3" ros_from_system: true }
  host { name: "pi" address: "10.0.0.4" }
"""
SPLIT = (
    """
robot_config {
  name: "split"
  mode: MODE_INFERENCE"""
    + HOSTS
    + """
  discovery { server_host: "arm" port: 11811 }
  dashboard { host: "gpu" zenoh_connect: "tcp/10.0.0.9:7447" zenoh_password_file: "/etc/joshua/gpu-secret" }
  node { name: "camera" type: CAMERA_PUBLISHER topic_name: "/camera/image_raw" camera_index: 2 }
  node { name: "local_policy_input" type: MOCK_ACTUATOR_SUBSCRIBER topic_name: "/follower/commands" }
  node { name: "follower" type: ACTUATOR_SUBSCRIBER topic_name: "/follower/commands"
         serial_port: "/dev/ttyARM" state_topic: "/follower/joint_states" }
  node { name: "policy" type: INFERENCE host: "gpu" topic_name: "/follower/commands"
         input_topics: ["/camera/image_raw", "/follower/joint_states"] model_path: "/models/act" }
  node { name: "leader" type: ENCODER_PUBLISHER host: "pi" topic_name: "/leader/joint_states"
         serial_port: "/dev/ttyPI" }
}
"""
)
NO_HOSTS = """
robot_config {
  name: "split"
  mode: MODE_TELEOPERATION
  node { name: "leader" type: MOCK_ENCODER_PUBLISHER topic_name: "/leader/joint_states" }
}
"""


def checked(text: str, path: str = "split.pbtxt"):
    result = check_text(path, text)
    assert not result.has_errors, format_text(result.diagnostics, result.sources)
    return result


def files_of(text: str) -> dict[str, str]:
    result = checked(text)
    return render(result.robot or plan(result.description, "split.pbtxt"))


def host_files(files: dict[str, str], host: str) -> dict[str, str]:
    prefix = f"hosts/{host}/"
    return {path[len(prefix) :]: text for path, text in files.items() if path.startswith(prefix)}


def test_each_host_gets_a_complete_output_with_only_its_own_processes():
    files = files_of(SPLIT)
    assert {path for path in files if not path.startswith("hosts/")} == {
        "manifest.json",
        "topology.dot",
        "topology.mmd",
    }
    processes = {
        "arm": {"discovery_server", "camera", "local_policy_input", "follower", "host_agent_arm"},
        "gpu": {"policy", "dashboard", "host_agent_gpu"},
        "pi": {"leader", "host_agent_pi"},
    }
    for host, names in processes.items():
        part = host_files(files, host)
        for path in ("supervisor.py", "supervisord.conf", "manifest.json", "fastdds_profile.xml", "topology.dot"):
            assert path in part, (host, path)
        assert {path[len("nodes/") : -3] for path in part if path.startswith("nodes/")} == names
        units = {path for path in part if path.startswith("systemd/") and path.endswith(".service")}
        assert units == {f"systemd/joshua-split-{name}.service" for name in names}
        assert set(re.findall(r"^\[program:(\w+)\]", part["supervisord.conf"], re.M)) == names
        data = supervisor_data(plan(checked(SPLIT).description, "split.pbtxt").for_host(host))
        assert data["host"] == host and {p["name"] for p in data["processes"]} == names


def test_the_manifest_places_every_node_and_tells_each_host_where_the_others_are():
    files = files_of(SPLIT)
    whole = json.loads(files["manifest.json"])
    assert {node["name"]: node["host"] for node in whole["nodes"]} == {
        "camera": "arm",
        "local_policy_input": "arm",
        "follower": "arm",
        "policy": "gpu",
        "leader": "pi",
    }
    assert "host" not in whole
    assert whole["discovery"] == {"host": "arm", "address": "10.0.0.2", "port": 11811}
    assert [(h["name"], h["address"], h["processes"]) for h in whole["hosts"]] == [
        ("arm", "10.0.0.2", ["discovery_server", "camera", "local_policy_input", "follower", "host_agent_arm"]),
        ("gpu", "10.0.0.3", ["policy", "dashboard", "host_agent_gpu"]),
        ("pi", "10.0.0.4", ["leader", "host_agent_pi"]),
    ]
    pi = json.loads(files["hosts/pi/manifest.json"])
    assert pi["host"] == "pi" and pi["hosts"] == whole["hosts"] and pi["discovery"] == whole["discovery"]
    assert [node["name"] for node in pi["nodes"]] == ["leader"]
    assert pi["devices"] == [{"kind": "serial", "path": "/dev/ttyPI", "node": "leader", "host": "pi"}]


def test_no_host_output_holds_another_hosts_devices_or_secrets():
    files = files_of(SPLIT)
    own = {
        "arm": ["/dev/ttyARM", "/dev/video2"],
        "gpu": ["/etc/joshua/gpu-secret", "/models/act"],
        "pi": ["/dev/ttyPI"],
    }
    for host in own:
        text = "\n".join(host_files(files, host).values())
        for other, values in own.items():
            for value in values:
                assert (value in text) == (other == host), (host, value)


def test_processes_find_each_other_through_the_discovery_server_as_super_clients():
    files = files_of(SPLIT)
    for host in ("arm", "gpu", "pi"):
        for profile in ("fastdds_profile.xml", "fastdds_profile_images.xml"):
            text = host_files(files, host)[profile]
            assert "<discoveryProtocol>SUPER_CLIENT</discoveryProtocol>" in text
            assert re.search(r"<address>10\.0\.0\.2</address>\s*<port>11811</port>", text), text
            assert 'prefix="44.53.00.5f.45.50.52.4f.53.49.4d.41"' in text
    without_server = files_of(SPLIT.replace('discovery { server_host: "arm" port: 11811 }', ""))
    plain = files_of(NO_HOSTS)
    for profile in ("fastdds_profile.xml", "fastdds_profile_images.xml"):
        assert host_files(without_server, "arm")[profile] == plain[profile]


def test_a_remote_policy_reads_the_cameras_jpeg_copy_and_local_readers_keep_the_raw_images():
    robot = plan(checked(SPLIT).description, "split.pbtxt")
    topics = {topic.name: topic for topic in robot.topics}
    copy = topics["/camera/image_raw/compressed"]
    assert copy.message_type == "sensor_msgs/msg/CompressedImage"
    assert [e.node for e in copy.publishers] == ["camera"] and [e.node for e in copy.subscribers] == ["policy"]
    assert [e.node for e in topics["/camera/image_raw"].subscribers] == []
    camera = robot.node("camera").settings
    assert camera.compressed_topic.name == "/camera/image_raw/compressed"
    assert camera.compressed_topic.qos == camera.topic.qos
    assert [t.name for t in robot.node("policy").settings.inputs] == [
        "/camera/image_raw/compressed",
        "/follower/joint_states",
    ]
    assert image_key("/camera/image_raw/compressed") == image_key("/camera/image_raw") == "camera"
    beside = SPLIT.replace('node { name: "policy" type: INFERENCE host: "gpu"', 'node { name: "policy" type: INFERENCE')
    robot = plan(checked(beside).description, "split.pbtxt")
    assert "/camera/image_raw/compressed" not in {t.name for t in robot.topics}
    assert not robot.node("camera").settings.compressed_topic.name


def test_a_host_with_ros_from_apt_runs_its_nodes_after_sourcing_the_ros_setup():
    files = files_of(SPLIT)
    gpu = host_files(files, "gpu")["systemd/joshua-split-policy.service"]
    exec_start = next(line for line in gpu.splitlines() if line.startswith("ExecStart="))
    assert exec_start.startswith('ExecStart=/bin/sh -c ". /opt/ros/jazzy/setup.sh && exec \\"$$0\\" \\"$$@\\"" ')
    assert ". /opt/ros/jazzy/setup.sh" in host_files(files, "gpu")["supervisord.conf"]
    arm = host_files(files, "arm")["systemd/joshua-split-follower.service"]
    assert "setup.sh" not in arm
    assert "After=joshua-split-discovery_server.service" in arm
    assert "After=" not in host_files(files, "pi")["systemd/joshua-split-leader.service"]


@pytest.mark.process
@pytest.mark.parametrize("host", ["arm", "gpu", "pi"])
def test_each_hosts_units_pass_systemd_analyze_verify_where_they_are_deployed(tmp_path, host):
    source = tmp_path / "split.pbtxt"
    source.write_text(SPLIT)
    deployed = tmp_path / "deployed"
    built = joshuac("build", source, "-o", tmp_path / "out", "--prefix", deployed)
    assert built.returncode == 0, built.stderr
    shutil.copytree(tmp_path / "out" / "hosts" / host, deployed)
    units = sorted(str(path) for path in (deployed / "systemd").iterdir())
    result = subprocess.run([SYSTEMD_ANALYZE, "verify", *units], capture_output=True, text=True, cwd=deployed)
    assert (result.returncode, result.stderr, result.stdout) == (0, "", "")


def test_a_description_without_hosts_builds_exactly_as_before():
    files = files_of(NO_HOSTS)
    assert not any(path.startswith("hosts/") for path in files)
    assert (
        '"host' not in files["manifest.json"]
        and "starts_first" not in files["supervisor.py"].split("ROBOT = ")[1][:4000]
    )


def test_devices_belong_to_their_nodes_host():
    two_hosts = """
robot_config {
  name: "split"
  mode: MODE_TELEOPERATION
  host { name: "arm" address: "10.0.0.2" }
  host { name: "bench" address: "10.0.0.3" }
  node { name: "leader" type: ENCODER_PUBLISHER host: "bench" topic_name: "/leader/joint_states" serial_port: "/dev/ttyUSB0" }
  node { name: "follower" type: ACTUATOR_SUBSCRIBER topic_name: "/leader/joint_states" serial_port: "/dev/ttyUSB0" }
  node { name: "front" type: CAMERA_PUBLISHER host: "bench" topic_name: "/front" }
  node { name: "wrist" type: CAMERA_PUBLISHER topic_name: "/wrist" }
}
"""
    assert [d.code for d in check_text("split.pbtxt", two_hosts).diagnostics] == []
    one_host = two_hosts.replace('host: "bench" ', "")
    found = [(d.code, d.line, d.message) for d in check_text("split.pbtxt", one_host).diagnostics]
    assert found == [
        ("E401", 8, 'serial port "/dev/ttyUSB0" of host "arm" is already claimed by node "leader"'),
        ("E402", 10, 'camera index 0 of host "arm" is already used by node "front" (camera_index defaults to 0)'),
    ]


def test_the_discovery_server_name_is_reserved_with_a_discovery_block():
    text = SPLIT.replace('name: "leader" type: ENCODER_PUBLISHER', 'name: "discovery_server" type: ENCODER_PUBLISHER')
    found = [(d.code, d.message) for d in check_text("split.pbtxt", text).diagnostics if d.code == "E205"]
    assert found == [("E205", 'node name "discovery_server" is reserved for the Discovery Server process')]


@pytest.mark.process
def test_joshuac_run_needs_one_of_the_hosts(tmp_path):
    source = tmp_path / "split.pbtxt"
    source.write_text(SPLIT)
    missing = joshuac("run", source)
    assert (missing.returncode, missing.stderr) == (
        2,
        "joshuac: error: robot split runs on several hosts (arm, gpu, pi): run one with --host NAME on its computer\n",
    )
    unknown = joshuac("run", source, "--host", "laptop")
    assert (unknown.returncode, unknown.stderr) == (
        2,
        "joshuac: error: --host laptop: robot split has no such host (hosts: arm, gpu, pi)\n",
    )
    plain = tmp_path / "plain.pbtxt"
    plain.write_text(NO_HOSTS)
    assert joshuac("run", plain, "--host", "arm").returncode == 2


@pytest.mark.process
def test_each_hosts_bundle_installs_only_what_its_processes_need():
    from joshua_codegen.bundle import bundle_files

    bundle = bundle_files(plan(checked(SPLIT).description, "split.pbtxt"))
    assert not any(path.startswith(("wheels/", "install.sh")) for path in bundle)

    def packages(host: str) -> set[str]:
        text = bundle[f"hosts/{host}/wheels/requirements.txt"]
        return {line.split("==")[0] for line in text.splitlines() if line[:1].isalpha()}

    pi, arm, gpu = packages("pi"), packages("arm"), packages("gpu")
    assert "torch" not in pi and "torch" not in arm and "torch" in gpu  # only the policy's host gets the ai extra
    assert "ros-jazzy-rclpy" in pi and "ros-rcl" in pi and "empy" in pi  # ROS from PyPI, with what only it needs
    assert not {name for name in gpu if name.startswith("ros-")} and "empy" not in gpu  # ROS from apt
    assert {"numpy", "setuptools", "lerobot"} <= gpu  # also needed by others than ROS: kept
    gpu_install = bundle["hosts/gpu/install.sh"]
    assert "python=${PYTHON:-/usr/bin/python3}" in gpu_install
    assert ". /opt/ros/jazzy/setup.sh" in gpu_install
    assert "uv venv --quiet --allow-existing --system-site-packages" in gpu_install
    assert '"$python" -m venv --system-site-packages "$venv"' in gpu_install
    assert (
        "setup.sh" not in bundle["hosts/pi/install.sh"]
        and "--system-site-packages" not in bundle["hosts/pi/install.sh"]
    )


@pytest.mark.process
def test_each_hosts_output_carries_a_stamp_of_its_own_that_sha256sum_accepts(tmp_path):
    source = tmp_path / "split.pbtxt"
    source.write_text(SPLIT)
    out = tmp_path / "out"
    assert joshuac("build", source, "-o", out).returncode == 0
    for host in ("arm", "gpu", "pi"):
        copy = tmp_path / host
        shutil.copytree(out / "hosts" / host, copy)
        checked = subprocess.run(["sha256sum", "--check", "--strict", "--quiet", ".joshuac-stamp"], cwd=copy)
        assert checked.returncode == 0, host
        lines = (copy / ".joshuac-stamp").read_text().splitlines()
        listed = {line.split("  ", 1)[1] for line in lines if not line.startswith("#")}
        assert listed == {str(p.relative_to(copy)) for p in copy.rglob("*") if p.is_file()} - {".joshuac-stamp"}
    again = joshuac("build", source, "-o", out)  # the output is joshuac's own, so it is replaced
    assert again.returncode == 0, again.stderr


@pytest.mark.process
def test_build_check_compares_every_hosts_output(tmp_path):
    source = tmp_path / "split.pbtxt"
    source.write_text(SPLIT)
    out = tmp_path / "out"
    assert joshuac("build", source, "-o", out).returncode == 0
    same = joshuac("build", source, "-o", out, "--check")
    assert (same.returncode, same.stdout) == (0, ""), same.stderr
    (out / "hosts" / "pi" / "nodes" / "leader.py").write_text("edited\n")
    (out / "hosts" / "gpu" / ".joshuac-stamp").unlink()
    changed = joshuac("build", source, "-o", out, "--check")
    assert changed.returncode == 1
    assert "(2 files differ: hosts/gpu/.joshuac-stamp (missing), hosts/pi/nodes/leader.py (changed))" in changed.stderr
