"""The simulated 2D laser: rays cast on an occupancy mask by the one ray caster
(:func:`pmk_nb.wire.first_hits`: all rays at once, in blocks of steps half a cell apart), each range
backed off half a step from the first sample inside a wall.

Rays that hit nothing within ``range_max`` report ``+inf`` (REP 117). A blind sector (a covered
or failed sensor: ``blind``, angles relative to the scanner) reports ``NaN``. On the wire both
become JSON ``null``, exactly as real rosbridge servers send them (JSON has no NaN or Infinity),
so clients see what they see from a real chair: ``null`` = unknown.
"""

from __future__ import annotations

import math

import numpy as np

from pmk_nb.wire import FIRST_BLOCK, first_hits


class Laser:
    """A planar scanner centred on base_link, ``rays`` beams spread evenly over ``fov`` radians."""

    def __init__(
        self,
        rays: int = 720,
        fov: float = math.radians(270.0),
        range_min: float = 0.05,
        range_max: float = 10.0,
        block: int = FIRST_BLOCK,
        blind: tuple[float, float] | None = None,
    ) -> None:
        if rays < 2:
            raise ValueError(f"a laser needs at least 2 rays, got {rays}")
        self.rays = rays
        self.angle_min = -fov / 2.0
        self.angle_increment = fov / (rays - 1)
        self.range_min = range_min
        self.range_max = range_max
        self.block = block
        self.angles = self.angle_min + self.angle_increment * np.arange(rays)
        self.blind = blind

    @property
    def blind(self) -> tuple[float, float] | None:
        """(start, end) in radians of the rays that report NaN, or None."""
        return self._blind

    @blind.setter
    def blind(self, sector: tuple[float, float] | None) -> None:
        if sector is not None:
            lo, hi = sorted(float(a) for a in sector)
            sector = (lo, hi)
        self._blind = sector
        self._blind_mask = (
            None if sector is None else (self.angles >= sector[0] - 1e-9) & (self.angles <= sector[1] + 1e-9)
        )

    def cast(
        self, hit: np.ndarray, resolution: float, origin: tuple[float, float], pose: tuple[float, float, float]
    ) -> np.ndarray:
        """Ranges (float32, metres) for a scanner at ``pose`` (map frame) over the ``hit`` mask."""
        x, y, theta = pose
        step = 0.5 * resolution
        gx, gy = (x - origin[0]) / resolution, (y - origin[1]) / resolution
        ang = theta + self.angles
        dx, dy = np.cos(ang) * 0.5, np.sin(ang) * 0.5  # cells per step

        def cells(rays: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            return gx + dx[rays, None] * t, gy + dy[rays, None] * t

        first = first_hits(hit, cells, self.rays, int(self.range_max / step) + 1, block=self.block)
        ranges = np.full(self.rays, np.inf, dtype=np.float32)
        got = first >= 0
        # the sample is inside the wall cell; back off half a step for an unbiased range
        ranges[got] = np.maximum((first[got] - 0.5) * step, self.range_min)
        if self._blind_mask is not None:
            ranges[self._blind_mask] = np.nan
        return ranges
