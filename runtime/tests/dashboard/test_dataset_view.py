"""`joshua-dataset view` in Debian's headless Chromium: every episode listed with its task, its video and joint plots.

The dataset: two episodes (tasks pick and place) converted with `joshua-dataset from-bag --videos`
from a bag of the project's bag writer and merged, so both live in one mp4 per camera. The page
must not report any error (dashboard_support's watched browser).
"""

import json
import re
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest
from dashboard_support import browser, screenshot

from testsupport.arm_bag import CAMERA, FOLLOWER, LEADER, write_arm_bag

DATASET = str(Path(sys.executable).parent / "joshua-dataset")
BAG_HZ, BAG_S, FPS, WIDTH, HEIGHT = 30, 2.0, 10, 64, 48
CLI_TIMEOUT_S = 300
SERVER_TIMEOUT_S = 60
OFFLINE = {"HF_HUB_OFFLINE": "1", "HF_DATASETS_OFFLINE": "1", "TRANSFORMERS_OFFLINE": "1"}
pytestmark = [pytest.mark.ai, pytest.mark.browser]  # LeRobot writes the dataset; Chromium shows it


def run(env, *arguments) -> None:
    result = subprocess.run(
        [DATASET, *map(str, arguments)], env=env, capture_output=True, text=True, timeout=CLI_TIMEOUT_S
    )
    assert result.returncode == 0, result.stderr


@pytest.fixture
def ai_env(ros_env, tmp_path) -> dict:
    """The tools' environment: the test's ROS domain, offline, Hugging Face caches of this test."""
    return dict(
        ros_env, **OFFLINE, HF_DATASETS_CACHE=str(tmp_path / "hf-cache"), HF_LEROBOT_HOME=str(tmp_path / "lerobot")
    )


@pytest.fixture
def dataset(tmp_path, ai_env):
    bag = write_arm_bag(tmp_path / "session", BAG_HZ, BAG_S, WIDTH, HEIGHT)
    common = ["--action", LEADER, "--inputs", FOLLOWER, CAMERA, "--fps", FPS, "--videos"]
    for task in ("pick", "place"):
        run(ai_env, "from-bag", bag, tmp_path / task, *common, "--task", task)
    run(ai_env, "merge", tmp_path / "merged", tmp_path / "pick", tmp_path / "place")
    return tmp_path / "merged"


def test_view_lists_the_episodes_with_task_video_and_joint_plots(dataset, ai_env):
    viewer = subprocess.Popen(
        [DATASET, "view", dataset], env=ai_env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        line = viewer.stdout.readline()
        found = re.fullmatch(rf"viewing {dataset} at (http://127\.0\.0\.1:\d+/) \(Ctrl-C stops\)\n", line)
        assert found, (line, viewer.stderr.read() if viewer.poll() is not None else "")
        url = found.group(1)
        with browser() as chromium:
            page = chromium.new_page()
            page.goto(url)
            page.get_by_test_id("episode-1").wait_for(timeout=SERVER_TIMEOUT_S * 1000)
            assert page.get_by_test_id("episode-0").inner_text().endswith("pick")
            frames = json.loads((dataset / "meta" / "info.json").read_text())["total_frames"]
            assert page.locator("#title").inner_text() == f"{dataset}: 2 episodes, {frames} frames at {FPS} fps"

            page.get_by_test_id("episode-1").click()
            page.locator("#episode-task").filter(has_text="Task: place").wait_for()
            plot = page.get_by_test_id("plot-action")
            plot.wait_for()
            assert plot.locator("polyline").count() == 2  # one line per joint
            assert page.get_by_test_id("plot-observation.state").locator("polyline").count() == 2
            video = page.get_by_test_id("video-observation.images.camera")
            # The second episode's span of the shared mp4: the page seeks there once the metadata is in.
            page.wait_for_function(
                "v => v.readyState >= 1 && v.currentTime >= 1.9", arg=video.element_handle(), timeout=30000
            )
            source = video.get_attribute("src")
            with urllib.request.urlopen(url.rstrip("/") + source) as response:
                assert response.status == 200 and response.read(12)[4:8] == b"ftyp"  # an mp4
            screenshot(page, "dataset_view")
    finally:
        viewer.terminate()
        viewer.wait(SERVER_TIMEOUT_S)
