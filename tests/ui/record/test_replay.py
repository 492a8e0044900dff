"""The replay of a recording (issue 40): record the simulated chair driving, then the picture and its
text follow the time slider; Home's Record panel offers Replay for the recording it finished."""

from __future__ import annotations

import datetime as dt
import math
import re
import time
from pathlib import Path

import pytest

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


def _panel_replay(panel: RecordPanel, opening: object) -> ReplayView:
    assert opening is not None
    opening.join(30)  # type: ignore[attr-defined]
    view = panel.replay_view
    assert view is not None and list(panel.replay_slot.children) == [view.widget], panel.open_status.value
    return view


def test_any_mcap_in_the_folder_replays_with_a_plot_that_follows_the_slider(tmp_path: Path) -> None:
    """A ``ros2 bag`` MCAP copied into the recordings folder: listed, opened, the chair and the plot's
    cursor follow the slider; a file gone since the list was made is said, not raised."""
    from pmk_nb.ui.record.panel import recordings_dir
    from tests.ros2_bags import SPEED, write_drive_bag

    bag = write_drive_bag(tmp_path / "elsewhere", seconds=4.0)
    with app_context(tmp_path) as ctx:
        folder = recordings_dir(ctx)
        folder.mkdir(parents=True)
        (folder / "drive.mcap").write_bytes(bag.read_bytes())
        panel = RecordPanel(ctx)
        try:
            assert panel.files.value == "drive.mcap" and not panel.open_button.disabled
            view = _panel_replay(panel, panel.open_chosen())
            assert "Replaying drive.mcap: 4.0 s" in panel.open_status.value
            assert view.field.value == ("/odom", "twist.twist.linear.x")  # the chair's speed, plotted first
            start_cursor, start_pose = view.plot.value, _pose_in(view.caption.value)
            view.slider.value = view.slider.max
            assert math_dist(start_pose, _pose_in(view.caption.value)) == pytest.approx(SPEED * 4.0, abs=0.06)
            assert f"= {SPEED:.4g} at 4.0 s" in view.value.value and view.plot.value != start_cursor
            left = [float(x) for x in re.findall(r"left: ([\d.]+)%", start_cursor + view.plot.value)]
            assert left[0] < left[1]  # the cursor moved right with the slider
            view.field.value = ("/odom", "pose.pose.position.x")  # another field: drawn at the same time
            assert "pose.pose.position.x = 2 at 4.0 s" in view.value.value

            (folder / "drive.mcap").unlink()  # gone since the list was made
            assert panel.open_chosen() is None
            assert "no such recording" in panel.open_status.value and panel.files.options == ()
            assert panel.open_button.disabled
        finally:
            panel.close()


def test_an_upload_is_kept_in_the_folder_and_replayed_and_a_bad_one_is_said(tmp_path: Path) -> None:
    from pmk_nb.ui.record.panel import recordings_dir
    from tests.ros2_bags import write_drive_bag

    data = write_drive_bag(tmp_path / "device", seconds=2.0).read_bytes()
    with app_context(tmp_path) as ctx:
        panel = RecordPanel(ctx)
        try:
            assert panel.files.options == () and panel.open_button.disabled  # nothing recorded yet
            rosbag1 = memoryview(b"#ROSBAG V2.0\n")  # as the page's FileUpload sends a file
            when = dt.datetime.now(dt.UTC)
            sent = {"name": "run.bag", "type": "", "size": 13, "content": rosbag1, "last_modified": when}
            panel.upload.value = (sent,)
            assert "does not end in .mcap" in panel.open_status.value and not recordings_dir(ctx).exists()
            for junk in ("junk", ({"name": 3, "content": b"x"},), ({"name": "a.mcap", "content": "text"},)):
                panel._on_upload({"new": junk})  # what a page may set the synced value to: nothing happens
            assert not recordings_dir(ctx).exists()
            opening = panel.store_upload("run.mcap", data)
            view = _panel_replay(panel, opening)
            assert (recordings_dir(ctx) / "run.mcap").read_bytes() == data
            assert panel.files.value == "run.mcap" and view.path == recordings_dir(ctx) / "run.mcap"
            assert "chair at x" in view.caption.value
        finally:
            panel.close()


def test_a_locked_kiosk_refuses_an_upload_but_replays(tmp_path: Path) -> None:
    from pmk_nb.errors import KioskLocked
    from pmk_nb.ui.kiosk.pin import KioskLock, PinStore
    from pmk_nb.ui.record.panel import recordings_dir
    from tests.ros2_bags import write_drive_bag

    bag = write_drive_bag(tmp_path / "device", seconds=1.0)
    PinStore(tmp_path / "cfg").set_pin("4711", "4711")
    with app_context(tmp_path) as ctx:
        ctx.kiosk = KioskLock(PinStore(ctx.config_dir))
        panel = RecordPanel(ctx)
        try:
            with pytest.raises(KioskLocked):
                panel.store_upload("run.mcap", bag.read_bytes())
            assert not recordings_dir(ctx).exists()
            recordings_dir(ctx).mkdir(parents=True)
            (recordings_dir(ctx) / "run.mcap").write_bytes(bag.read_bytes())
            panel.list_files()
            assert "chair at x" in _panel_replay(panel, panel.open_chosen()).caption.value  # reading needs no PIN
        finally:
            panel.close()
