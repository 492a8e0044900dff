"""A recording's replay timeline: where the chair was, what its laser saw and the plan it followed, at any time.

Pure (numpy only): the dashboard's replay draws what :meth:`Timeline.at` returns. Time is the
``received`` column (the recorder's clock, one clock for every topic: the chair's header stamps may come
from several clocks), in seconds since the first message. At time ``t`` each layer shows its latest
message at or before ``t``:

* pose: the first pose topic recorded, in this order: ``/amcl_pose`` (map frame), ``/odom``, then any
  Odometry, PoseWithCovarianceStamped or PoseStamped topic;
* laser: the scan's hits (finite ranges) placed round the pose the chair had at the scan's header stamp
  (the pose topic's messages interpolated by their own header stamps: a turning chair's hits stay on
  the walls, as RViz places them), else round the latest pose; the laser taken at the chair's centre;
* path: the latest ``nav_msgs/Path`` (``/plan`` first);
* map: the latest ``OccupancyGrid`` (``/map``), for the background.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

POSE_TYPES = ("nav_msgs/msg/Odometry", "geometry_msgs/msg/PoseWithCovarianceStamped", "geometry_msgs/msg/PoseStamped")
Rows = Sequence[Mapping[str, Any]]
#: a scan stamped this far (s) outside the poses' stamps is placed at the latest pose instead
STAMP_SLACK_S = 0.5


@dataclass(frozen=True)
class GridImage:
    """A recorded map: ``cells`` (height x width, int8, row 0 at the origin), ``resolution``, ``origin`` (x, y)."""

    cells: np.ndarray
    resolution: float
    origin: tuple[float, float]

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(left, right, bottom, top) in metres, for an image drawn with its origin at the bottom."""
        h, w = self.cells.shape
        x0, y0 = self.origin
        return x0, x0 + w * self.resolution, y0, y0 + h * self.resolution


@dataclass(frozen=True)
class ReplayFrame:
    """What the replay shows at ``t`` (seconds since the recording began); None: no message yet."""

    t: float
    pose: tuple[float, float, float] | None  # x, y, yaw
    laser: np.ndarray | None  # (N, 2) hit points in the pose's frame
    path: np.ndarray | None  # (M, 2)


def _yaw(row: Mapping[str, Any], prefix: str) -> float:
    x, y = float(row.get(f"{prefix}x", 0.0)), float(row.get(f"{prefix}y", 0.0))
    z, w = float(row.get(f"{prefix}z", 0.0)), float(row.get(f"{prefix}w", 1.0))
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def _pose_prefix(row: Mapping[str, Any]) -> str:
    return "pose.pose." if "pose.pose.position.x" in row else "pose."


def _latest(times: np.ndarray, t: float) -> int | None:
    i = int(np.searchsorted(times, t, side="right")) - 1
    return i if i >= 0 else None


def _pick(types: Mapping[str, str], first: Sequence[str], wanted: Sequence[str]) -> str | None:
    for topic in first:
        if types.get(topic) in wanted:
            return topic
    return next((topic for topic, kind in sorted(types.items()) if kind in wanted), None)


class Timeline:
    """A recording's layers over time; build with :meth:`from_tables`."""

    def __init__(self, rows: Mapping[str, Rows], types: Mapping[str, str]) -> None:
        self.pose_topic = _pick(types, ("/amcl_pose", "/odom"), POSE_TYPES)
        self.scan_topic = _pick(types, ("/scan",), ("sensor_msgs/msg/LaserScan",))
        self.path_topic = _pick(types, ("/plan",), ("nav_msgs/msg/Path",))
        self.map_topic = _pick(types, ("/map",), ("nav_msgs/msg/OccupancyGrid",))
        received = [r["received"] for topic_rows in rows.values() for r in topic_rows]
        self.start = min(received) if received else 0.0
        self.duration = (max(received) - self.start) if received else 0.0
        #: every topic's rows (those with messages), and their times since the start, made when first asked
        self._rows: dict[str, list[Mapping[str, Any]]] = {t: list(rs) for t, rs in rows.items() if rs}
        self._times: dict[str, np.ndarray] = {}
        self._by_stamp = _poses_by_stamp(self._rows.get(self.pose_topic or "", []))
        maps = list(rows.get(self.map_topic) or ()) if self.map_topic else []
        self.grid = _grid(maps[-1]) if maps else None

    @classmethod
    def from_tables(cls, tables: Any) -> Timeline:
        """From :class:`~pmk_nb.recordings.read.Tables` (anything with ``rows`` and ``types``)."""
        return cls(tables.rows, tables.types)

    def _times_of(self, topic: str) -> np.ndarray:
        times = self._times.get(topic)
        if times is None:
            rows = self._rows.get(topic, [])
            times = self._times[topic] = np.array([r["received"] - self.start for r in rows], dtype=float)
        return times

    def _row(self, topic: str | None, t: float) -> Mapping[str, Any] | None:
        if topic is None or not self._rows.get(topic):
            return None
        i = _latest(self._times_of(topic), t)
        return None if i is None else self._rows[topic][i]

    @property
    def first_pose(self) -> float:
        """When the first pose arrived (seconds since the recording began; 0 without poses): where a replay starts."""
        times = self._times_of(self.pose_topic or "")
        return float(times[0]) if times.size else 0.0

    def poses(self, until: float | None = None) -> np.ndarray:
        """(N, 2) positions of the pose topic, those received up to ``until`` seconds (default: all)."""
        topic = self.pose_topic or ""
        rows = self._rows.get(topic, [])
        if until is not None and rows:
            rows = rows[: int(np.searchsorted(self._times_of(topic), until, side="right"))]
        prefix = _pose_prefix(rows[0]) if rows else ""
        points = [(r[f"{prefix}position.x"], r[f"{prefix}position.y"]) for r in rows]
        return np.array(points, dtype=float).reshape(-1, 2)

    def pose_at_stamp(self, stamp: object) -> tuple[float, float, float] | None:
        """The chair's pose at a header stamp, interpolated between the pose messages' own stamps (None:
        no stamp, no stamped poses, or a stamp more than :data:`STAMP_SLACK_S` outside them)."""
        table = self._by_stamp
        if table is None or not isinstance(stamp, int | float) or not math.isfinite(stamp):
            return None
        stamps, xs, ys, yaws = table
        if not stamps[0] - STAMP_SLACK_S <= stamp <= stamps[-1] + STAMP_SLACK_S:
            return None
        yaw = float(np.interp(stamp, stamps, yaws))
        return float(np.interp(stamp, stamps, xs)), float(np.interp(stamp, stamps, ys)), math.remainder(yaw, math.tau)

    def numeric_fields(self) -> list[tuple[str, str]]:
        """Every (topic, field) whose first message holds a number there: what the replay can plot."""
        found: list[tuple[str, str]] = []
        for topic in sorted(self._rows):
            found += [(topic, key) for key, value in self._rows[topic][0].items() if _plottable(key, value)]
        return found

    def default_field(self) -> tuple[str, str] | None:
        """The field a replay plots first: the chair's forward speed if recorded, else the first number."""
        fields = self.numeric_fields()
        for wanted in ("twist.twist.linear.x", "linear.x"):
            hit = next((f for f in fields if f[1] == wanted and f[0] == self.pose_topic), None)
            hit = hit or next((f for f in fields if f[1] == wanted), None)
            if hit:
                return hit
        return fields[0] if fields else None

    def series(self, topic: str, field: str) -> tuple[np.ndarray, np.ndarray]:
        """(times since the recording began, values) of ``field`` on ``topic``; NaN where a message lacks it."""
        rows = self._rows.get(topic, [])
        times = self._times_of(topic)
        values = np.array([_number(r.get(field)) for r in rows], dtype=float)
        return times, values

    def value_at(self, topic: str, field: str, t: float) -> float | None:
        """``field``'s latest value at or before ``t`` (None before its first message)."""
        times, values = self.series(topic, field)
        i = _latest(times, t)
        return None if i is None else float(values[i])

    def at(self, t: float) -> ReplayFrame:
        """The layers at ``t`` seconds since the recording began (clamped to the recording)."""
        t = min(max(t, 0.0), self.duration)
        pose = None
        row = self._row(self.pose_topic, t)
        if row is not None:
            prefix = _pose_prefix(row)
            position = (float(row[f"{prefix}position.x"]), float(row[f"{prefix}position.y"]))
            pose = (*position, _yaw(row, f"{prefix}orientation."))
        scan = self._row(self.scan_topic, t)
        laser = _hits(scan, self.pose_at_stamp(scan.get("stamp")) or pose) if scan is not None and pose else None
        plan = self._row(self.path_topic, t)
        path = _path(plan) if plan is not None else None
        return ReplayFrame(t, pose, laser, path)


def _poses_by_stamp(rows: Rows) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """(stamps, x, y, unwrapped yaw) of the pose rows with a finite header stamp, in stamp order."""
    if not rows:
        return None
    prefix = _pose_prefix(rows[0])
    x, y, turn = f"{prefix}position.x", f"{prefix}position.y", f"{prefix}orientation."
    table = [
        (float(r["stamp"]), float(r[x]), float(r[y]), _yaw(r, turn))
        for r in rows
        if isinstance(r.get("stamp"), int | float) and math.isfinite(r["stamp"]) and x in r
    ]
    if not table:
        return None
    arr = np.array(sorted(table), dtype=float)
    return arr[:, 0], arr[:, 1], arr[:, 2], np.unwrap(arr[:, 3])


def _plottable(key: str, value: object) -> bool:
    if key in ("received", "stamp") or isinstance(value, bool):
        return False
    return isinstance(value, int | float | np.integer | np.floating)


def _number(value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        return math.nan
    return float(value)


def _hits(scan: Mapping[str, Any], pose: tuple[float, float, float]) -> np.ndarray:
    ranges = np.asarray(scan.get("ranges", ()), dtype=float)
    angles = float(scan.get("angle_min", 0.0)) + float(scan.get("angle_increment", 0.0)) * np.arange(ranges.size)
    hit = np.isfinite(ranges) & (ranges >= float(scan.get("range_min", 0.0)))
    hit &= ranges <= float(scan.get("range_max", np.inf))
    x, y, yaw = pose
    a = angles[hit] + yaw
    return np.column_stack([x + ranges[hit] * np.cos(a), y + ranges[hit] * np.sin(a)])


def _path(plan: Mapping[str, Any]) -> np.ndarray:
    poses = plan.get("poses") or []
    points = [(p.get("pose.position.x", math.nan), p.get("pose.position.y", math.nan)) for p in poses]
    return np.array(points, dtype=float).reshape(-1, 2)


def _grid(row: Mapping[str, Any]) -> GridImage | None:
    width, height = int(row.get("info.width", 0)), int(row.get("info.height", 0))
    data = np.asarray(row.get("data", ()), dtype=np.int8)
    if width <= 0 or height <= 0 or data.size != width * height:
        return None
    origin = (float(row.get("info.origin.position.x", 0.0)), float(row.get("info.origin.position.y", 0.0)))
    return GridImage(data.reshape(height, width), float(row.get("info.resolution", 1.0)), origin)
