"""What the simulated chair knows about the current map: collision, laser targets, planning grid.

Rebuilt once per map load (and on hot reload), never per tick. Unknown cells (-1) count as blocked
for driving — a real chair must not roll into unmapped space — but the laser only sees occupied
cells, as a real laser sees only physical walls. Map yaw is ignored (as AMCL and costmaps do).
Construction builds only what driving and the laser need; the planning grid is built on first
use (in a worker thread: planning always runs off the loop), so a hot reload of a big map is fast.
"""

from __future__ import annotations

import math
import threading

import numpy as np

from pmk_nb.grid import OccupancyGrid
from pmk_nb.sim.gridops import clearance, descend, dilate_disk, erosion_depth, wavefront

OCCUPIED_AT = 50  # cells >= this are walls (trinary maps only hold 0/100/-1)
PLAN_MAX_CELLS = 200  # longest side of the downsampled planning grid
CLEAR_CAP = 1.0  # m: clearance beyond this makes no difference to planning
WALL_BAND = 0.4  # m: planning cells closer than this to the collision limit cost up to 3x more


class World:
    """Masks derived from an occupancy grid and a circular footprint."""

    def __init__(self, grid: OccupancyGrid, footprint_radius: float = 0.35) -> None:
        self.grid = grid
        self.footprint = footprint_radius
        data = grid.data
        res = grid.resolution
        self.hit = data >= OCCUPIED_AT  # laser targets
        self.blocked = dilate_disk(self.hit | (data < 0), footprint_radius / res)  # chair centre may not enter
        self.has_free = not bool(self.blocked.all())  # somewhere the footprint fits
        self.factor = max(1, math.ceil(max(grid.width, grid.height) / PLAN_MAX_CELLS))
        self._plan_lock = threading.Lock()
        self._planned = False

    @property
    def plan_free(self) -> np.ndarray:
        """Free cells of the downsampled planning grid (built on first use; call off the loop)."""
        self._ensure_planning_grid()
        return self._plan_free

    def _ensure_planning_grid(self) -> None:
        with self._plan_lock:
            if not self._planned:
                self._build_planning_grid()
                self._planned = True

    def _build_planning_grid(self) -> None:
        """Downsample for planning without losing narrow doors.

        Each planning cell is represented by its fine cell farthest from the collision limit, and
        is free if that cell is: a 0.9 m door leaves the chair's centre a gap of only a few fine
        cells, which plain sampling would miss. Cells near walls cost more, so paths keep to the
        middle of corridors and doors.
        """
        res, f = self.grid.resolution, self.factor
        cap = max(1, round(CLEAR_CAP / res))
        clear = erosion_depth(~self.blocked, cap)  # 0 on blocked cells, >= 1 on free ones
        h, w = clear.shape
        hp, wp = -(-h // f) * f, -(-w // f) * f
        padded = np.full((hp, wp), -1.0)
        padded[:h, :w] = clear
        blocks = padded.reshape(hp // f, f, wp // f, f).transpose(0, 2, 1, 3).reshape(hp // f, wp // f, f * f)
        best = blocks.argmax(axis=2)
        value = np.take_along_axis(blocks, best[..., None], axis=2)[..., 0]
        self._plan_free = value > 0
        drow, dcol = np.divmod(best, f)
        self._rep_row = np.arange(hp // f)[:, None] * f + drow
        self._rep_col = np.arange(wp // f)[None, :] * f + dcol
        near = np.clip(1.0 - value * res / WALL_BAND, 0.0, 1.0)
        self._plan_weight = 1.0 + 2.0 * near

    # -- lookups ----------------------------------------------------------------------------------

    def blocked_at(self, x: float, y: float) -> bool:
        col, row = self.grid.world_to_cell(x, y)
        if 0 <= col < self.grid.width and 0 <= row < self.grid.height:
            return bool(self.blocked[row, col])
        return True

    def nearest_free(self, x: float, y: float) -> tuple[float, float] | None:
        """Centre of the free cell (for the footprint) closest to (x, y); None if the map has none.

        Searches square windows around (x, y) that double in size, so a chair a little off the
        free space of a huge map costs a few small windows, not a scan of every cell.
        """
        h, w = self.blocked.shape
        col, row = self.grid.world_to_cell(x, y)
        col, row = min(max(col, 0), w - 1), min(max(row, 0), h - 1)
        half = 16
        while True:
            found = self._nearest_in(x, y, row, col, half)
            if found is not None or half >= max(h, w):
                break
            half *= 2
        if found is None:
            return None
        # the window is a square, distances are round: a free cell just outside it may be nearer
        reach = math.ceil(found[2] / self.grid.resolution) + 1
        if reach > half:
            found = self._nearest_in(x, y, row, col, reach)
        assert found is not None
        return found[0], found[1]

    def _nearest_in(self, x: float, y: float, row: int, col: int, half: int) -> tuple[float, float, float] | None:
        """(x, y, distance) of the free cell nearest (x, y) within ``half`` cells of (row, col)."""
        r0, c0 = max(row - half, 0), max(col - half, 0)
        rows, cols = np.nonzero(~self.blocked[r0 : row + half + 1, c0 : col + half + 1])
        if rows.size == 0:
            return None
        res, (ox, oy, _) = self.grid.resolution, self.grid.origin
        cx, cy = ox + (cols + c0 + 0.5) * res, oy + (rows + r0 + 0.5) * res
        d2 = (cx - x) ** 2 + (cy - y) ** 2
        i = int(np.argmin(d2))
        return float(cx[i]), float(cy[i]), math.sqrt(float(d2[i]))

    def open_spot(self) -> tuple[float, float]:
        """The most open free point: largest clearance on the planning grid (the "largest free area")."""
        free = self.plan_free
        if not free.any():
            spot = self.nearest_free(*self.grid.cell_center(self.grid.width // 2, self.grid.height // 2))
            if spot is None:
                raise ValueError("the map has no cell where the chair's footprint fits")
            return spot
        clear = np.where(free, clearance(free), -1.0)
        rows, cols = np.nonzero(clear >= clear.max() - 0.5)  # the most open cells; take the middle one
        i = int(np.argmin((rows - rows.mean()) ** 2 + (cols - cols.mean()) ** 2))
        x, y = self._plan_to_world(int(rows[i]), int(cols[i]))
        if self.blocked_at(x, y):
            spot = self.nearest_free(x, y)
            assert spot is not None
            return spot
        return x, y

    # -- planning -------------------------------------------------------------------------------

    def _world_to_plan(self, x: float, y: float) -> tuple[int, int]:
        col, row = self.grid.world_to_cell(x, y)
        h, w = self.plan_free.shape
        return min(max(row // self.factor, 0), h - 1), min(max(col // self.factor, 0), w - 1)

    def _plan_to_world(self, row: int, col: int) -> tuple[float, float]:
        return self.grid.cell_center(int(self._rep_col[row, col]), int(self._rep_row[row, col]))

    def _snap(self, cell: tuple[int, int], radius: int = 3) -> tuple[int, int] | None:
        """The planning cell itself if free, else the nearest free one within ``radius`` cells."""
        r, c = cell
        h, w = self.plan_free.shape
        r0, r1, c0, c1 = max(r - radius, 0), min(r + radius + 1, h), max(c - radius, 0), min(c + radius + 1, w)
        rows, cols = np.nonzero(self.plan_free[r0:r1, c0:c1])
        if rows.size == 0:
            return None
        i = int(np.argmin((rows + r0 - r) ** 2 + (cols + c0 - c) ** 2))
        return int(rows[i] + r0), int(cols[i] + c0)

    def plan(self, start: tuple[float, float], goal: tuple[float, float]) -> list[tuple[float, float]]:
        """Waypoints (world metres) from start to goal avoiding inflated obstacles; [] if no path."""
        s, g = self._snap(self._world_to_plan(*start)), self._snap(self._world_to_plan(*goal))
        if s is None or g is None:
            return []
        sources = np.zeros_like(self.plan_free)
        sources[g] = True
        cells = descend(wavefront(self.plan_free, sources, weight=self._plan_weight), s)
        if not cells:
            return []
        points = [self._plan_to_world(r, c) for r, c in _corners(cells)]
        if math.dist(points[-1], goal) > 1e-6 and not self.blocked_at(*goal):
            points.append(goal)
        return points

    def reachable_points(
        self, start: tuple[float, float], rng: np.random.Generator, k: int = 1
    ) -> list[tuple[float, float]]:
        """``k`` random free points reachable from ``start`` (for patrol)."""
        s = self._snap(self._world_to_plan(*start))
        if s is None:
            return []
        sources = np.zeros_like(self.plan_free)
        sources[s] = True
        dist = wavefront(self.plan_free, sources)
        rows, cols = np.nonzero(np.isfinite(dist) & (dist * self.factor * self.grid.resolution > 1.5))
        if rows.size == 0:
            return []
        pick = rng.choice(rows.size, size=min(k, rows.size), replace=False)
        return [self._plan_to_world(int(rows[i]), int(cols[i])) for i in pick]


def _corners(cells: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Drop cells in the middle of straight runs; keep the ends and every turn."""
    if len(cells) <= 2:
        return cells
    out = [cells[0]]
    for prev, cur, nxt in zip(cells, cells[1:], cells[2:], strict=False):
        if (cur[0] - prev[0], cur[1] - prev[1]) != (nxt[0] - cur[0], nxt[1] - cur[1]):
            out.append(cur)
    out.append(cells[-1])
    return out
