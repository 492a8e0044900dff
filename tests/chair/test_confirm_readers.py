"""The deploy's cell check reads our file as the chair's map server does (issue 40, item 8).

A scale-mode map reads differently under ROS 1's rules and Nav2's: read with ROS 1's, a map a Nav2
chair had loaded was reported as 'a map of the same size but different cells'.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

from pmk_nb.chair.confirm import ExpectedMap, confirm_map
from pmk_nb.errors import DeployError
from pmk_nb.grid import OccupancyGrid
from pmk_nb.rosmap import MapFiles, read_map
from pmk_nb.rosmap.image import ImageReader

SCALE_YAML = "image: m.pgm\nmode: scale\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
SCALE_YAML += "occupied_thresh: 0.65\nfree_thresh: 0.196\n"


@dataclass
class Info:
    width: int
    height: int
    resolution: float
    origin: tuple[float, float, float]


class ChairPublishing:
    """A link to a chair whose map server has loaded our file with ``reader``; no PMK MapInfo."""

    is_connected = True

    def __init__(self, grid: OccupancyGrid, ros_version: int | None) -> None:
        self.grid = grid
        self.ros_version = ros_version

    def map_info(self, timeout: float) -> Info:
        return Info(self.grid.width, self.grid.height, self.grid.resolution, (0.0, 0.0, 0.0))

    def fetch_map(self, timeout: float) -> OccupancyGrid:
        return self.grid


def _scale_map(folder: Path) -> MapFiles:
    (folder / "m.pgm").write_bytes(b"P5\n16 16\n255\n" + bytes(range(256)))
    (folder / "m.yaml").write_text(SCALE_YAML)
    files = MapFiles(folder / "m.yaml", folder / "m.pgm", None)
    assert (read_map(files.yaml).data != read_map(files.yaml, reader="nav2_jazzy").data).any()  # the readers differ
    return files


@pytest.mark.parametrize(("reader", "version"), [("nav2_jazzy", 2), ("nav2_humble", 2), ("ros1", 1), ("ros1", None)])
def test_a_scale_mode_map_the_chair_loaded_is_confirmed(tmp_path: Path, reader: ImageReader, version: int) -> None:
    files = _scale_map(tmp_path)
    link = ChairPublishing(read_map(files.yaml, reader=reader), version)
    expected = ExpectedMap(16, 16, 0.1, (0.0, 0.0))
    info, how = confirm_map(link, expected, None, files, timeout=5.0)
    assert how == "cells" and info.width == 16


def test_a_ros1_chair_publishing_nav2s_cells_is_still_a_different_map(tmp_path: Path) -> None:
    files = _scale_map(tmp_path)
    link = ChairPublishing(read_map(files.yaml, reader="nav2_jazzy"), 1)
    with pytest.raises(DeployError, match="different cells") as caught:
        confirm_map(link, ExpectedMap(16, 16, 0.1, (0.0, 0.0)), None, files, timeout=1.0)
    assert caught.value.step == "confirm"
