"""`joshuac build`: deterministic, atomic output that leaves nothing stale, and `--check`."""

import os
import py_compile
import shutil

import pytest

from joshua_codegen.render import NOT_SCRIPTS
from testsupport.joshuac_cli import CONFIGS, ROOT, joshuac

pytestmark = pytest.mark.process  # joshuac's command line


def tree(directory):
    return {
        p.relative_to(directory).as_posix(): (p.read_bytes(), p.stat().st_mode & 0o777)
        for p in sorted(directory.rglob("*"))
        if p.is_file()
    }


@pytest.mark.parametrize("config", CONFIGS, ids=lambda p: p.stem)
def test_same_input_gives_identical_trees_across_directories_seeds_zones_and_locales(config, tmp_path):
    outputs = []
    for i, (seed, zone, lang) in enumerate([("0", "UTC", "C.UTF-8"), ("12345", "Asia/Tokyo", "de_DE.UTF-8")]):
        workdir = tmp_path / f"w{i}" / "nested"
        workdir.mkdir(parents=True)
        shutil.copy(config, workdir / config.name)
        env = dict(os.environ, PYTHONHASHSEED=seed, TZ=zone, LANG=lang, LC_ALL=lang)
        result = joshuac("build", config.name, "-o", "out", cwd=workdir, env=env)
        assert result.returncode == 0, result.stderr
        outputs.append(tree(workdir / "out"))
    assert outputs[0] == outputs[1]
    text = b"".join(content for content, _ in outputs[0].values())
    assert str(tmp_path).encode() not in text


@pytest.mark.parametrize("config", CONFIGS, ids=lambda p: p.stem)
def test_every_generated_python_file_compiles_and_scripts_are_executable(config, tmp_path):
    result = joshuac("build", config, "-o", tmp_path / "out")
    assert result.returncode == 0, result.stderr
    files = sorted((tmp_path / "out").rglob("*.py"))
    scripts = [path for path in files if path.name not in NOT_SCRIPTS]
    assert scripts
    for script in scripts:
        py_compile.compile(str(script), doraise=True)
        assert script.stat().st_mode & 0o777 == 0o755
        assert script.read_text().startswith("#!/usr/bin/env python3\n")
        assert "DO NOT EDIT" in script.read_text().splitlines()[1]
    for module in set(files) - set(scripts):  # code a script runs
        py_compile.compile(str(module), doraise=True)
        assert module.stat().st_mode & 0o777 == 0o644
        assert "DO NOT EDIT" in module.read_text().splitlines()[0]


def test_rebuild_removes_files_of_nodes_that_are_gone(tmp_path):
    config = tmp_path / "robot.pbtxt"
    text = (ROOT / "config/robots/mock_arm.pbtxt").read_text()
    config.write_text(text)
    out = tmp_path / "out"
    assert joshuac("build", config, "-o", out).returncode == 0
    assert (out / "nodes" / "lidar.py").exists()
    start = text.index("  # Synthetic room scan.")
    config.write_text(text[:start] + "}\n")
    assert joshuac("build", config, "-o", out).returncode == 0
    assert not (out / "nodes" / "lidar.py").exists()
    assert (out / "nodes" / "camera.py").exists()


def test_failed_build_leaves_the_output_as_it_was(tmp_path):
    config = tmp_path / "robot.pbtxt"
    config.write_text((ROOT / "config/robots/mock_arm.pbtxt").read_text())
    out = tmp_path / "out"
    assert joshuac("build", config, "-o", out).returncode == 0
    before = tree(out)
    config.write_text(config.read_text().replace("MOCK_LIDAR_PUBLISHER", "MOCK_LIDAR_PUBLISHR"))
    result = joshuac("build", config, "-o", out)
    assert result.returncode == 1
    assert "MOCK_LIDAR_PUBLISHR" in result.stderr
    assert tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "robot.pbtxt"]


def test_build_refuses_to_replace_a_directory_it_did_not_write(tmp_path):
    out = tmp_path / "precious"
    out.mkdir()
    (out / "thesis.tex").write_text("years of work")
    result = joshuac("build", ROOT / "config/robots/mock_arm.pbtxt", "-o", out)
    assert result.returncode == 1
    assert "refusing to replace" in result.stderr
    assert (out / "thesis.tex").read_text() == "years of work"


def test_check_flag_prints_a_diff_and_exits_1_only_when_output_differs(tmp_path):
    config = ROOT / "config/robots/mock_arm.pbtxt"
    out = tmp_path / "out"
    assert joshuac("build", config, "-o", out).returncode == 0
    same = joshuac("build", config, "-o", out, "--check")
    assert (same.returncode, same.stdout) == (0, "")
    manifest = out / "manifest.json"
    manifest.write_text(manifest.read_text().replace('"mock_arm"', '"edited"', 1))
    (out / "nodes" / "stale.py").write_text("x = 1\n")
    (out / "nodes" / "camera.py").unlink()
    changed = joshuac("build", config, "-o", out, "--check")
    assert changed.returncode == 1
    assert '-    "name": "edited",' in changed.stdout
    assert '+    "name": "mock_arm",' in changed.stdout
    assert "--- a/nodes/stale.py\n+++ /dev/null\n" in changed.stdout
    assert "--- /dev/null\n+++ b/nodes/camera.py\n" in changed.stdout
    assert f"joshuac build {config} -o {out}" in changed.stderr


def test_set_overrides_a_field_before_validation(tmp_path):
    config = ROOT / "config/robots/mock_arm.pbtxt"
    out = tmp_path / "out"
    result = joshuac("build", config, "-o", out, "--set", "camera.qos_depth=2", "--set", "name=other_arm")
    assert result.returncode == 0, result.stderr
    text = (out / "nodes" / "camera.py").read_text()
    assert "'robot': 'other_arm'," in text
    assert "'depth': 2," in text


@pytest.mark.parametrize(
    "prefix",
    [
        "relative/dir",
        "/opt/robot\nExecStart=/bin/evil",
        "/a/../b",
        "//a",
        "/a/./b",
        "/opt/robot/",
        "/opt/a=b",
        "/opt/" + "x" * 256,
        "/x" * 2000,
    ],
)
def test_prefix_must_be_an_absolute_printable_normalized_path_that_fits(prefix, tmp_path):
    result = joshuac("build", ROOT / "config/robots/mock_arm.pbtxt", "-o", tmp_path / "out", "--prefix", prefix)
    assert result.returncode == 2
    assert "Invalid value for '--prefix'" in result.stderr
    assert not (tmp_path / "out").exists()
