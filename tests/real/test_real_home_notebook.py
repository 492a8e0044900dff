"""Real-stack tier: Home's live view and notebook 02 against rosbridge-server-rs + the rclpy nodes (issue 9).

The same flows as the simulator tests (tests/ui/live/test_live.py, tests/kernels/test_notebooks.py), but the chair
is a real ROS 2 graph behind a real rosbridge server: Home goes Live, draws frames with the chair and
its laser, drives the sim node with the Drive joystick's channel; notebook 02 records from a saved
chair profile.
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path
from typing import Any

import nbformat
import pytest
from nbclient import NotebookClient

from pmk_nb.chair import ChairProfile, ProfileStore
from pmk_nb.library import MapsFolder
from pmk_nb.ui import AppContext
from tests import fixtures_ros2
from tests.fixtures_ros2 import RealChair
from tests.fixtures_sim import room_grid, write_test_map
from tests.helpers import wait_until

ros2_stack, real_chair = fixtures_ros2.ros2_stack, fixtures_ros2.real_chair
NOTEBOOKS = Path(__file__).resolve().parents[2] / "notebooks"


@pytest.fixture
def chair(real_chair: RealChair) -> RealChair:
    """Bridge (no rosapi, as a plain chair) + map server + sim node on an 8 m x 6 m room."""
    write_test_map(room_grid(8.0, 6.0), real_chair.maps, "room")
    real_chair.start_bridge()
    real_chair.start_map_server("room")
    real_chair.start_sim_node("--map", "room")
    real_chair.wait_service("/map_server/map_info", "map_server_pmk/srv/MapInfo")
    return real_chair


@pytest.mark.slow
def test_home_goes_live_draws_frames_and_drives_the_real_chair(chair: RealChair, tmp_path: Path) -> None:
    from pmk_nb.ui.home.screen import HomeScreen

    profiles = ProfileStore(tmp_path / "profiles.json", secrets=False)
    profiles.save(ChairProfile(name="real", host="127.0.0.1", port=chair.port, max_linear=0.4))
    ctx = AppContext(MapsFolder(tmp_path / "maps"), profiles, config_dir=tmp_path / "cfg")
    ctx.set_current_map("room", chair.maps / "room.yaml", None)
    home = HomeScreen(ctx, canvas_width=320, canvas_height=240, fps=20)
    try:
        home.preview_button.click()
        assert wait_until(lambda: home.connection_state()[0] == "live", 30.0), home.ui.warning.value
        assert wait_until(lambda: home.live.metrics.last_pose is not None, 10.0)
        # parked, the view draws on change only: the first scan's arrival is one
        assert wait_until(lambda: home.live.metrics.last_hits > 20, 10.0)  # the real laser's hits reach the canvas

        # the Drive toggle and its channel drive the sim node through the real bridge
        drive = home.drive
        assert drive.toggle.layout.display == "" and drive.session is None
        drive.toggle.value = True
        assert drive.session is not None
        x0 = home.live.metrics.last_pose[0]
        frames0 = home.live.metrics.frames
        t0 = time.monotonic() * 1000.0
        for seq in range(1, 16):
            msg = {"page": "ui", "seq": seq, "press": 1, "t": t0 + seq * 100.0, "x": 0.0, "y": 1.0}
            drive.channel.value = json.dumps({**msg, "held": True, "hidden": False})
            time.sleep(0.1)
        moved = home.live.metrics.last_pose[0] - x0
        drawn = home.live.metrics.frames - frames0
        drive.toggle.value = False  # Drive off: one zero, then silence
        assert drawn >= 10, f"{drawn} frames in 1.5 s of driving at 20 fps"  # a lower bound, not a speed goal
        odom = ctx.link().latest_odom()
        assert math.hypot(moved, 0.0) > 0.1, f"moved {moved:.2f} m"
        assert wait_until(lambda: abs(ctx.link().latest_odom().v) < 0.01, 2.0), odom
    finally:
        home.close()
        ctx.close()


@pytest.mark.slow
def test_notebook_02_records_the_real_chair_from_a_saved_profile(
    chair: RealChair, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PMK_CONFIG_DIR", str(tmp_path / "config"))
    monkeypatch.setenv("PMK_MAPS_DIR", str(tmp_path / "maps"))
    monkeypatch.setenv("PMK_RECORD_SECONDS", "4")
    monkeypatch.setenv("PMK_CHAIR_PROFILE", "real chair")
    monkeypatch.delenv("MPLBACKEND", raising=False)
    ProfileStore(secrets=False).save(ChairProfile(name="real chair", host="127.0.0.1", port=chair.port))
    nb: Any = nbformat.read(NOTEBOOKS / "02-chair-data.ipynb", as_version=4)
    NotebookClient(nb, kernel_name="python3", timeout=180, resources={"metadata": {"path": str(NOTEBOOKS)}}).execute()
    outs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    text = "".join(o.get("text", "") for o in outs)
    assert f"ws://127.0.0.1:{chair.port}" in text and "Started a simulated chair" not in text
    recorded = [line.split() for line in text.splitlines() if line.startswith("recorded ")]
    assert recorded and int(recorded[0][1]) > 20 and int(recorded[0][5]) > 4, text  # odometry and scans
    assert len([o for o in outs if "image/png" in o.get("data", {})]) >= 2  # the map and the scan plots
