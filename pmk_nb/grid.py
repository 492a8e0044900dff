"""The in-memory occupancy map shared by the converter, the map files and the chair link.

Grid row 0 is the *bottom* row (ROS ``nav_msgs/OccupancyGrid`` order); image row 0 is the top.
Values follow ``OccupancyGrid.data``: -1 unknown, 0 free, 100 occupied (1..99 in scale mode).
"""

from __future__ import annotations

import math
import mmap
from dataclasses import dataclass, field
from typing import Any

import numpy as np

UNKNOWN = -1
FREE = 0
OCCUPIED = 100
#: Greys of a map image as map_saver writes them: 0 occupied, 254 free, 205 unknown, 1..99 as shades.
GRAY_UNKNOWN = 205


def _gray_lut() -> np.ndarray:
    values = np.arange(256, dtype=np.uint8).view(np.int8).astype(np.int16)
    lut = np.rint((100 - values.clip(0, 100)) * 254 / 100).astype(np.uint8)
    lut[(values < 0) | (values > 100)] = GRAY_UNKNOWN
    lut.setflags(write=False)
    return lut


#: occupancy byte (int8 viewed as uint8) -> grey: one lookup for the map file and the live view
GRAY_LUT = _gray_lut()


@dataclass
class OccupancyGrid:
    """A 2D occupancy grid in a metric frame.

    Attributes:
        data: int8 array of shape (height, width); ``data[0]`` is the bottom row.
        resolution: metres per cell.
        origin: (x, y, yaw) of the lower-left corner of cell (0, 0) in metres.
        frame_id: the ROS frame the grid lives in.
        meta: extra facts carried into the YAML (storey, source, sha256, georeference...).
    """

    data: np.ndarray
    resolution: float
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    frame_id: str = "map"
    meta: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.data.ndim != 2:
            raise ValueError(f"occupancy data must be 2D, got shape {self.data.shape}")
        if self.data.dtype != np.int8:
            self.data = self.data.astype(np.int8)
        if not (self.resolution > 0 and np.isfinite(self.resolution)):
            raise ValueError(f"resolution must be a positive number of metres per cell, got {self.resolution}")
        self.origin = (float(self.origin[0]), float(self.origin[1]), float(self.origin[2]))

    @property
    def width(self) -> int:
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        return int(self.data.shape[0])

    @property
    def size_m(self) -> tuple[float, float]:
        return self.width * self.resolution, self.height * self.resolution

    def world_to_cell(self, x: float, y: float) -> tuple[int, int]:
        """(column, row) of the cell containing world point (x, y); may be outside the grid."""
        return (
            int(np.floor((x - self.origin[0]) / self.resolution)),
            int(np.floor((y - self.origin[1]) / self.resolution)),
        )

    def cell_center(self, col: int, row: int) -> tuple[float, float]:
        return (
            self.origin[0] + (col + 0.5) * self.resolution,
            self.origin[1] + (row + 0.5) * self.resolution,
        )

    def value_at(self, x: float, y: float) -> int | None:
        """Cell value at world (x, y), or None outside the grid."""
        col, row = self.world_to_cell(x, y)
        if 0 <= col < self.width and 0 <= row < self.height:
            return int(self.data[row, col])
        return None

    def to_ros_data(self) -> list[int]:
        """Row-major, bottom row first: the order of ``OccupancyGrid.data``."""
        return self.data.reshape(-1).tolist()

    @classmethod
    def from_ros_msg(cls, msg: dict[str, Any]) -> OccupancyGrid:
        """Build from a rosbridge ``nav_msgs/OccupancyGrid`` message dict."""
        info = msg["info"]
        width, height = int(info["width"]), int(info["height"])
        raw = msg["data"]
        if isinstance(raw, str):  # rosbridge may send uint8[]/int8[] as base64 on some servers
            import base64

            arr = np.frombuffer(base64.b64decode(raw), dtype=np.int8)
        else:
            arr = np.asarray(raw, dtype=np.int16).astype(np.int8)
        if arr.size != width * height:
            raise ValueError(f"OccupancyGrid has {arr.size} cells, expected {width}x{height}")
        pos = info["origin"]["position"]
        q = info["origin"].get("orientation", {"z": 0.0, "w": 1.0})
        yaw = float(2.0 * np.arctan2(q.get("z", 0.0), q.get("w", 1.0)))
        frame = msg.get("header", {}).get("frame_id", "map") or "map"
        return cls(
            data=arr.reshape(height, width).copy(),
            resolution=float(info["resolution"]),
            origin=(float(pos["x"]), float(pos["y"]), yaw),
            frame_id=frame,
        )


_MMAP_MIN_BYTES = 32 * 1024 * 1024


def new_cells(height: int, width: int, value: int) -> np.ndarray:
    """A C-contiguous int8 (height, width) array filled with ``value``.

    Large grids live in their own anonymous mapping rather than numpy's allocator: numpy advises
    the kernel to back big arrays with huge pages, and on hosts that compact memory for them on first
    touch (transparent_hugepage defrag "madvise") that costs three to four times the pages themselves
    (a 400 MB grid: ~1 s of CPU against ~0.25 s). Freed with the array, like any other.

    Raises:
        MemoryError: the memory is not there (as numpy would).
    """
    size = height * width
    if size < _MMAP_MIN_BYTES:
        return np.full((height, width), value, np.int8)
    try:
        buf = mmap.mmap(-1, size, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
    except OSError as err:  # ENOMEM: the same answer numpy gives
        raise MemoryError(f"cannot map {size} bytes for a {width} x {height} grid") from err
    cells = np.frombuffer(buf, dtype=np.int8).reshape(height, width)
    cells.fill(value)
    return cells


def nice_ceil(value: float) -> float:
    """``value`` rounded up to two significant digits (0.01234 -> 0.013): a resolution to suggest."""
    if value <= 0 or not math.isfinite(value):
        return value
    step = 10.0 ** (math.floor(math.log10(value)) - 1)
    return float(f"{math.ceil(value / step - 1e-9) * step:.12g}")
