"""The simulated navigation stack's layers, published as Nav2 (or move_base) names them (issue 40).

A global costmap from the map with inflation (lethal walls, the inscribed radius, costs decaying out
to the inflation radius as costmap_2d's inflation layer does), a local costmap window that rolls with
the chair (in ``odom``), the chair's footprint, the local plan while a goal runs and a MarkerArray of
the goal: what a researcher sees in RViz, so the dashboard's layers can be tried without a robot.
Each is sent only while someone subscribes; the costmaps' cell values use the OccupancyGrid scale
(0 free .. 98, 99 inscribed, 100 lethal, -1 unknown).

As Nav2's costmap publisher does (``always_send_full_costmap: false``), the global costmap goes whole
to a new subscriber and when the map changes, and between those as ``map_msgs/OccupancyGridUpdate``
patches on ``<costmap>_updates``: each second, the window its obstacle layer updates round the chair,
grown to cover any cell marked since (:meth:`SimNavLayers.mark`: what a laser hit on a person makes).
The whole costmap is also repeated every few seconds, standing in for the transient-local durability
that lets a late subscriber of a real Nav2 get the last full costmap (rosbridge subscribes as one
client for all pages).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from pmk_nb.grid import OccupancyGrid
from pmk_nb.sim.gridops import dilate_disk
from pmk_nb.sim.jsonfast import RawJSON, int8_array_json
from pmk_nb.wire import pose_msg, vec3

if TYPE_CHECKING:
    from pmk_nb.sim.chair import Chair
    from pmk_nb.sim.messages import Names
    from pmk_nb.sim.protocol import Bridge

LETHAL, INSCRIBED, UNKNOWN = 100, 99, -1
INFLATION_M = 0.55  # Nav2's default inflation_radius
SCALING = 3.0  # Nav2's default cost_scaling_factor
RINGS = 8  # cost steps between the inscribed and the inflation radius
LOCAL_SIZE_M = 4.0  # a 4 m x 4 m rolling window, as a small Nav2 local costmap
GLOBAL_REPEAT_S = 5.0
GLOBAL_UPDATE_S = 1.0  # Nav2's global costmap publish_frequency
LOCAL_PERIOD_S = 0.5
FOOTPRINT_PERIOD_S = 0.2
PLAN_PERIOD_S = 0.2
MARKERS_PERIOD_S = 1.0
LOCAL_PLAN_M = 1.5
FOOTPRINT_SIDES = 16


def inflated_costs(grid: OccupancyGrid, inscribed_m: float, inflation_m: float = INFLATION_M) -> np.ndarray:
    """The map's costs as a global costmap publishes them: walls 100, within the chair's radius 99,
    then exponentially lower out to ``inflation_m``, unknown -1 (int8, row 0 = bottom)."""
    data = np.asarray(grid.data)
    walls = data >= 65
    res = float(grid.resolution)
    costs = np.zeros(data.shape, dtype=np.int8)
    outer = max(inflation_m, inscribed_m + res)
    steps = np.linspace(outer, inscribed_m, RINGS + 1)[:-1]  # outermost ring first: nearer rings overwrite it
    for d in steps:
        # costmap_2d: 252 * exp(-scaling * (d - inscribed)) on 0..254, here on the 0..100 scale
        cost = max(1, min(98, round(98 * math.exp(-SCALING * (d - inscribed_m)))))
        costs[dilate_disk(walls, d / res)] = cost
    costs[dilate_disk(walls, inscribed_m / res)] = INSCRIBED
    costs[walls] = LETHAL
    costs[data < 0] = UNKNOWN
    return costs


def _square(grid: OccupancyGrid, centre: tuple[float, float], size_m: float) -> tuple[int, int, int, int]:
    """Rows and columns (r0, r1, c0, c1) of the ``size_m`` square round ``centre``, cell-aligned with the
    map; it may reach beyond the map."""
    res = float(grid.resolution)
    n = max(1, round(size_m / res))
    col0 = math.floor((centre[0] - grid.origin[0]) / res) - n // 2
    row0 = math.floor((centre[1] - grid.origin[1]) / res) - n // 2
    return row0, row0 + n, col0, col0 + n


def window(costs: np.ndarray, grid: OccupancyGrid, centre: tuple[float, float], size_m: float) -> OccupancyGrid:
    """The ``size_m`` square of ``costs`` around ``centre``, cell-aligned with the map (outside: free, as a
    local costmap that does not track unknown space)."""
    res = float(grid.resolution)
    row0, _, col0, _ = _square(grid, centre, size_m)
    n = max(1, round(size_m / res))
    out = np.zeros((n, n), dtype=np.int8)
    rows, cols = costs.shape
    r0, r1, c0, c1 = max(row0, 0), min(row0 + n, rows), max(col0, 0), min(col0 + n, cols)
    if r0 < r1 and c0 < c1:
        out[r0 - row0 : r1 - row0, c0 - col0 : c1 - col0] = costs[r0:r1, c0:c1]
    origin = (grid.origin[0] + col0 * res, grid.origin[1] + row0 * res, 0.0)
    return OccupancyGrid(out, res, origin, frame_id="odom")


def _union(a: tuple[int, int, int, int], b: tuple[int, int, int, int]) -> tuple[int, int, int, int]:
    return min(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), max(a[3], b[3])


@dataclass(frozen=True)
class LayerTopics:
    """Where the layers go: Nav2's names on ROS 2, move_base's on ROS 1."""

    global_costmap: str
    local_costmap: str
    footprint: str
    local_plan: str
    markers: str = "/waypoints"  # Nav2's waypoint markers (its RViz panel's MarkerArray)

    @staticmethod
    def for_ros(ros: str) -> LayerTopics:
        if ros == "ros1":
            return LayerTopics(
                "/move_base/global_costmap/costmap",
                "/move_base/local_costmap/costmap",
                "/move_base/local_costmap/footprint",
                "/move_base/DWAPlannerROS/local_plan",
            )
        return LayerTopics(
            "/global_costmap/costmap", "/local_costmap/costmap", "/local_costmap/published_footprint", "/local_plan"
        )


class SimNavLayers:
    """Publishes the layers from the engine's odometry loop (``tick``), each at its own pace."""

    def __init__(self, names: Names, footprint_radius: float) -> None:
        self.names = names
        self.footprint_radius = float(footprint_radius)
        self.topics = LayerTopics.for_ros(names.ros)
        self.grid: OccupancyGrid | None = None
        self.costs: np.ndarray | None = None
        self._global_msg: dict[str, Any] | None = None
        self._due: dict[str, float] = {}
        self._had_global_subs = False
        self._markers_shown = False
        self._dirty: tuple[int, int, int, int] | None = None  # rows r0:r1, cols c0:c1 marked since the last patch

    def attach(self, bridge: Bridge) -> None:
        n, t = self.names, self.topics
        grid_type = n.msg("nav_msgs", "OccupancyGrid")
        update_type = n.msg("map_msgs", "OccupancyGridUpdate")
        bridge.advertise_internal(t.global_costmap, grid_type)
        bridge.advertise_internal(f"{t.global_costmap}_updates", update_type)
        bridge.advertise_internal(t.local_costmap, grid_type)
        bridge.advertise_internal(f"{t.local_costmap}_updates", update_type)
        bridge.advertise_internal(t.footprint, n.msg("geometry_msgs", "PolygonStamped"))
        bridge.advertise_internal(t.local_plan, n.msg("nav_msgs", "Path"))
        bridge.advertise_internal(t.markers, n.msg("visualization_msgs", "MarkerArray"))

    def build(self, grid: OccupancyGrid, now: float) -> tuple[np.ndarray, dict[str, Any]]:
        """A map's costs and its global costmap message (call off the loop: the inflation and the JSON
        take a moment on big maps); :meth:`use` puts them in place."""
        costs = inflated_costs(grid, self.footprint_radius)
        costmap = OccupancyGrid(costs, grid.resolution, grid.origin, frame_id="map")
        return costs, self.names.occupancy_grid(costmap, now, now)

    def use(self, grid: OccupancyGrid, costs: np.ndarray, msg: dict[str, Any]) -> None:
        """Publish ``grid``'s costmaps from now on (the global one at once to its subscribers)."""
        self.grid, self.costs, self._global_msg = grid, costs, msg
        self._dirty = None
        self._due.pop("global", None)

    def mark(self, x: float, y: float, radius_m: float) -> int:
        """Mark a lethal disc at (x, y) in the global costmap, as the obstacle layer marks a laser hit on
        something the map does not have; the next patch carries it. Returns the cells marked.

        Called from another thread: the arrays are replaced, never changed in place under the loop.
        """
        grid, costs = self.grid, self.costs
        if grid is None or costs is None:
            return 0
        res = float(grid.resolution)
        rows, cols = costs.shape
        r0, r1, c0, c1 = _square(grid, (x, y), 2.0 * radius_m + 4.0 * res)  # the disc's cells, and a margin
        r0, r1, c0, c1 = max(r0, 0), min(r1, rows), max(c0, 0), min(c1, cols)
        if r0 >= r1 or c0 >= c1:  # off the map
            return 0
        ys, xs = np.mgrid[r0:r1, c0:c1]
        cx, cy = (x - grid.origin[0]) / res - 0.5, (y - grid.origin[1]) / res - 0.5
        disc = (xs - cx) ** 2 + (ys - cy) ** 2 <= (radius_m / res) ** 2
        if not disc.any():
            return 0
        new = costs.copy()
        new[r0:r1, c0:c1][disc] = LETHAL
        hit_rows, hit_cols = np.nonzero(disc)
        top, left = r0 + int(hit_rows.min()), c0 + int(hit_cols.min())
        box = (top, r0 + int(hit_rows.max()) + 1, left, c0 + int(hit_cols.max()) + 1)
        if self._global_msg is not None:  # the same header and info, the new cells
            self._global_msg = {**self._global_msg, "data": RawJSON(int8_array_json(new))}
        self.costs = new
        self._dirty = box if self._dirty is None else _union(self._dirty, box)
        return int(disc.sum())

    def update_msg(self, centre: tuple[float, float], t: float) -> dict[str, Any] | None:
        """The patch of the window round ``centre`` and of the cells marked since the last one."""
        grid, costs = self.grid, self.costs
        if grid is None or costs is None:
            return None
        box = _square(grid, centre, LOCAL_SIZE_M)
        dirty, self._dirty = self._dirty, None
        if dirty is not None:
            box = _union(box, dirty)
        rows, cols = costs.shape
        r0, r1, c0, c1 = max(box[0], 0), min(box[1], rows), max(box[2], 0), min(box[3], cols)
        if r0 >= r1 or c0 >= c1:
            return None
        patch = costs[r0:r1, c0:c1]
        return {
            "header": self.names.header("map", t),
            "x": c0,
            "y": r0,
            "width": c1 - c0,
            "height": r1 - r0,
            "data": RawJSON(int8_array_json(patch)),
        }

    def _take(self, key: str, now: float, period: float) -> bool:
        if now < self._due.get(key, -math.inf):
            return False
        self._due[key] = now + period
        return True

    def tick(self, bridge: Bridge, chair: Chair, now: float, wall: float) -> None:
        """Publish what is due at loop time ``now`` (stamps: ``wall``, the chair's pose stamp)."""
        t = self.topics
        subs = bridge.has_subscribers(t.global_costmap)
        if subs and not self._had_global_subs:
            self._due.pop("global", None)  # a new subscriber: at once, as a latched costmap would be
        self._had_global_subs = subs
        if subs and self._global_msg is not None and self._take("global", now, GLOBAL_REPEAT_S):
            bridge.publish(t.global_costmap, self._global_msg)
            self._due["global_update"] = now + GLOBAL_UPDATE_S  # the whole costmap holds every patch
        updates = f"{t.global_costmap}_updates"
        if bridge.has_subscribers(updates) and self._take("global_update", now, GLOBAL_UPDATE_S):
            patch = self.update_msg(chair.pose[:2], wall)
            if patch is not None:
                bridge.publish(updates, patch)
        local_due = bridge.has_subscribers(t.local_costmap) and self._take("local", now, LOCAL_PERIOD_S)
        if local_due and self.costs is not None and self.grid is not None:
            local = window(self.costs, self.grid, chair.pose[:2], LOCAL_SIZE_M)
            bridge.publish(t.local_costmap, self.names.occupancy_grid(local, wall, wall))
        if bridge.has_subscribers(t.footprint) and self._take("footprint", now, FOOTPRINT_PERIOD_S):
            bridge.publish(t.footprint, self.footprint_msg(chair.pose, wall))
        if bridge.has_subscribers(t.local_plan) and self._take("plan", now, PLAN_PERIOD_S):
            ahead = chair.path_ahead(LOCAL_PLAN_M)
            if ahead:
                bridge.publish(t.local_plan, self.names.path(ahead, None, wall))
        if bridge.has_subscribers(t.markers) and self._take("markers", now, MARKERS_PERIOD_S):
            goal = chair.path_ahead(math.inf)
            if goal or self._markers_shown:
                bridge.publish(t.markers, self.markers_msg(goal, wall))
                self._markers_shown = bool(goal)

    def footprint_msg(self, pose: tuple[float, float, float], t: float) -> dict[str, Any]:
        """The chair's circle as a PolygonStamped in ``odom`` (the local costmap's frame)."""
        x, y, _ = pose
        r = self.footprint_radius
        angles = np.linspace(0.0, 2.0 * math.pi, FOOTPRINT_SIDES, endpoint=False)
        points = [vec3(round(x + r * math.cos(a), 4), round(y + r * math.sin(a), 4), 0.0) for a in angles]
        return {"header": self.names.header("odom", t), "polygon": {"points": points}}

    def markers_msg(self, path: list[tuple[float, float]], t: float) -> dict[str, Any]:
        """The goal as markers: a line strip to it, its points, an arrow, a cross and a label; with no
        goal, DELETEALL (the markers go)."""
        header = self.names.header("map", t)
        if not path:
            return {"markers": [{"header": header, "ns": "pmk_sim", "id": 0, "action": 3}]}
        gx, gy = path[-1]
        pts = [vec3(x, y, 0.0) for x, y in path]
        heading = math.atan2(gy - path[-2][1], gx - path[-2][0]) if len(path) > 1 else 0.0

        def marker(mid: int, kind: int, scale: float, rgba: tuple[float, ...], **extra: Any) -> dict[str, Any]:
            r, g, b, a = rgba
            return {
                "header": header,
                "ns": "pmk_sim",
                "id": mid,
                "type": kind,
                "action": 0,
                "pose": pose_msg(0.0, 0.0, 0.0),
                "scale": vec3(scale, scale, scale),
                "color": {"r": r, "g": g, "b": b, "a": a},
                **extra,
            }

        cross = [vec3(gx + dx, gy + dy, 0.0) for dx, dy in ((-0.2, -0.2), (0.2, 0.2), (-0.2, 0.2), (0.2, -0.2))]
        return {
            "markers": [
                marker(1, 4, 0.04, (0.1, 0.7, 0.2, 0.9), points=pts),  # LINE_STRIP: the way to the goal
                marker(2, 8, 0.08, (0.1, 0.4, 0.9, 1.0), points=pts[:: max(1, len(pts) // 12)]),  # POINTS
                marker(3, 5, 0.05, (0.9, 0.1, 0.1, 1.0), points=cross),  # LINE_LIST: a cross on the goal
                {
                    **marker(4, 0, 0.6, (1.0, 0.6, 0.0, 1.0)),
                    "pose": pose_msg(gx, gy, heading),
                    "scale": vec3(0.6, 0.1, 0.1),
                },  # ARROW
                {**marker(5, 9, 0.3, (0.0, 0.0, 0.0, 1.0), text="goal"), "pose": pose_msg(gx, gy + 0.4, 0.0)},  # TEXT
            ]
        }
