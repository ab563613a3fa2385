"""docs/two-computer-so100.md: its description builds, and each computer gets what the page says it gets."""

import json
import re
import subprocess

import pytest

from testsupport.joshuac_cli import ROOT, joshuac

pytestmark = pytest.mark.process  # joshuac's command line

PAGE = ROOT / "docs" / "two-computer-so100.md"
HOSTS = {
    "robot": {"discovery_server", "leader", "follower", "camera", "host_agent_robot"},
    "gpu": {"policy", "dashboard", "host_agent_gpu"},
}


def page_block(language: str, containing: str = "") -> str:
    blocks = re.findall(rf"^```{language}\n(.*?)^```$", PAGE.read_text(), re.MULTILINE | re.DOTALL)
    matching = [block for block in blocks if containing in block]
    assert len(matching) == 1, f"{PAGE.name}: expected one ```{language} block containing {containing!r}"
    return matching[0]


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    directory = tmp_path_factory.mktemp("two_computers")
    source = directory / "so100_two_computers.pbtxt"
    source.write_text(page_block("pbtxt"))
    command = page_block("sh", "joshuac build").split()
    assert command[:2] == ["joshuac", "build"]
    done = joshuac(*command[1:], cwd=directory)
    assert done.returncode == 0, done.stderr
    assert "warning" not in done.stderr, done.stderr
    return directory / "out"


def test_each_computer_gets_the_processes_the_page_lists(built):
    manifest = json.loads((built / "manifest.json").read_text())
    placed = {host["name"]: set(host["processes"]) for host in manifest["hosts"]}
    assert placed == HOSTS
    for host, processes in HOSTS.items():
        nodes = {path.stem for path in (built / "hosts" / host / "nodes").glob("*.py")}
        assert nodes == processes
    text = PAGE.read_text()
    for host, processes in HOSTS.items():
        assert all(f"`{name}" in text for name in processes), host


def test_the_robot_computer_gets_no_torch_and_the_gpu_machine_does(built):
    robot = (built / "hosts" / "robot" / "wheels" / "requirements.txt").read_text()
    gpu = (built / "hosts" / "gpu" / "wheels" / "requirements.txt").read_text()
    assert "\ntorch==" not in robot and "\nlerobot==" not in robot
    assert "\ntorch==" in gpu and "\nlerobot==" in gpu


def test_the_images_cross_as_jpeg_and_every_process_names_the_server_on_the_robot(built):
    manifest = json.loads((built / "manifest.json").read_text())
    policy = next(node for node in manifest["nodes"] if node["name"] == "policy")
    assert "/camera/image_raw/compressed" in json.dumps(policy)
    for host in HOSTS:
        profile = (built / "hosts" / host / "fastdds_profile.xml").read_text()
        assert "<address>192.168.1.20</address>" in profile and "<port>11811</port>" in profile


def test_the_copy_commands_name_files_the_build_wrote(built):
    for source in re.findall(r"rsync -a (out/hosts/\w+)/ ", page_block("sh", "rsync")):
        assert (built.parent / source / "supervisor.py").is_file(), source
    for path in re.findall(r"/opt/joshua/so100_two_computers/([\w./]+)", PAGE.read_text()):
        if "*" not in path:
            assert (built / "hosts" / "robot" / path).exists() or (built / "hosts" / "gpu" / path).exists(), path


def test_the_passwords_block_makes_a_password_per_host_and_the_dictionary(tmp_path):
    done = subprocess.run(
        ["bash", "-e", "-c", page_block("sh", "openssl rand")], cwd=tmp_path, capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 0, done.stderr
    users = (tmp_path / "control-users.txt").read_text().splitlines()
    assert [line.split(":")[0] for line in users] == list(HOSTS)
    assert all((tmp_path / f"{host}.control-password").stat().st_mode & 0o077 == 0 for host in HOSTS)
