"""The replay of a recording (issue 40): record the simulated chair driving, then the picture and its
text follow the time slider; Home's Record panel offers Replay for the recording it finished."""

from __future__ import annotations

import math
import re
import time
from pathlib import Path

from pmk_nb.chair import ChairProfile
from pmk_nb.ui.record.panel import RecordPanel
from pmk_nb.ui.record.replay import ReplayView
from tests.fixtures_sim import wait_until
from tests.helpers import app_context


def _pose_in(caption: str) -> tuple[float, float]:
    found = re.search(r"chair at x (-?[\d.]+) m, y (-?[\d.]+) m", caption)
    assert found, caption
    return float(found.group(1)), float(found.group(2))


def test_pose_laser_and_picture_follow_the_slider(sim_factory, link_factory, tmp_path: Path) -> None:
    sim = sim_factory(ros="ros2")
    link = link_factory(sim)
    path = tmp_path / "drive.mcap"
    recording = link.start_recording(path, ["/odom", "/scan", "/map"])
    recording.wait_flowing(30.0)
    deadline = time.monotonic() + 60.0
    while recording.stats.messages["/odom"] < 60 and time.monotonic() < deadline:
        link.publish_cmd_vel(0.5, 0.0)
        time.sleep(0.05)
    recording.stop()

    view = ReplayView(path)
    assert view.timeline.duration > 0.5 and view.timeline.grid is not None  # /map recorded: the background
    first_picture, first = view.picture.value, _pose_in(view.caption.value)
    assert 0 <= view.slider.value - view.timeline.first_pose < 0.1 + 1e-9  # it opens on the first pose, not before
    assert round(view.slider.value / 0.1, 6).is_integer()  # on a step: the page does not snap it back before it
    assert 'alt="Replay of drive.mcap: ' in first_picture and "chair at x" in first_picture
    view.slider.value = view.slider.max  # what the page's slider sends
    last = _pose_in(view.caption.value)
    assert math_dist(first, last) > 0.2, (first, last)  # the chair drove between the two ends
    assert view.frame.laser is not None and len(view.frame.laser) > 10
    assert "laser hits" in view.caption.value and view.picture.value != first_picture
    view.slider.value = 0.0  # the start: before the first pose, no chair
    assert "no pose yet" in view.caption.value or view.timeline.first_pose == 0.0
    view.slider.value = round(math.ceil(view.timeline.first_pose / 0.1) * 0.1, 6)  # back to where it opened
    assert _pose_in(view.caption.value) == first  # the same pose again
    view.slider.value = 0.0
    assert "no pose yet" in view.caption.value or view.timeline.first_pose == 0.0


def math_dist(a: tuple[float, float], b: tuple[float, float]) -> float:
    return ((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2) ** 0.5


def test_the_record_panel_replays_the_recording_it_finished(sim_factory, tmp_path: Path) -> None:
    sim = sim_factory()
    with app_context(tmp_path) as ctx:
        ctx.profiles.save(ChairProfile(name="sim", host="127.0.0.1", port=sim.port))
        panel = RecordPanel(ctx)
        try:
            assert panel.replay_button.layout.display == "none" and panel.replay() is None  # nothing recorded yet
            thread = panel.start()
            assert thread is not None
            thread.join(30)
            assert wait_until(lambda: panel.recording is not None and panel.recording.stats.total > 30, timeout=30)
            panel.stop().join(30)
            assert panel.replay_button.layout.display == ""
            opening = panel.replay()
            assert opening is not None
            opening.join(30)
            view = panel.replay_view
            assert view is not None and list(panel.replay_slot.children) == [view.widget], panel.status.value
            view.slider.value = view.slider.max
            assert view.path == panel.finished and "chair at x" in view.caption.value
        finally:
            panel.close()
