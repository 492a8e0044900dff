"""The navigation stack's own layers for the live map (issue 40): costmaps, footprint, local plan, markers.

Nav2 (and move_base, under ``/move_base/...``) publishes what it plans with: the global and local
costmaps (nav_msgs/OccupancyGrid ``.../global_costmap/costmap``, ``.../local_costmap/costmap``, then
map_msgs/OccupancyGridUpdate patches on ``..._updates``), the chair's footprint
(geometry_msgs/PolygonStamped ``/local_costmap/published_footprint``), the controller's local plan
(nav_msgs/Path ``/local_plan``) and anyone's visualization_msgs/MarkerArray. Each layer's topic is
found by its type through rosapi's ``topics_for_type`` (off the caller's thread, again every few
seconds while a wanted layer has none) and picked by Nav2's name among those of that type: nothing
is subscribed to guess, since a subscription names its type and would bring a topic into being.
Only the layers switched on are subscribed, each throttled; the I/O thread parses and stores.
"""

from __future__ import annotations

import functools
import logging
import math
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from pmk_nb.chair.link.streams.inspect import OwnSubscription  # a subscription that ends alone
from pmk_nb.chair.link.streams.planpath import PlannedPath, parse_path
from pmk_nb.errors import PmkError
from pmk_nb.viewport import PlanarMarker, normalise_frame
from pmk_nb.wire import yaw_from_quaternion

if TYPE_CHECKING:
    import roslibpy


__all__ = [
    "LAYERS",
    "Costmap",
    "CostmapUpdateOutside",
    "Footprint",
    "MarkerBoard",
    "NavLayerWatch",
    "apply_update",
    "parse_costmap",
    "parse_footprint",
    "parse_markers",
    "pick_topics",
]

log = logging.getLogger(__name__)

GLOBAL, LOCAL, FOOTPRINT, LOCAL_PLAN, MARKERS = "global_costmap", "local_costmap", "footprint", "local_plan", "markers"
LAYERS = (GLOBAL, LOCAL, FOOTPRINT, LOCAL_PLAN, MARKERS)
GRID_TYPE, UPDATE_TYPE = "nav_msgs/OccupancyGrid", "map_msgs/OccupancyGridUpdate"
POLYGON_TYPE, PATH_TYPE, MARKERS_TYPE = (
    "geometry_msgs/PolygonStamped",
    "nav_msgs/Path",
    "visualization_msgs/MarkerArray",
)
LAYER_TYPES = {
    GLOBAL: GRID_TYPE,
    LOCAL: GRID_TYPE,
    FOOTPRINT: POLYGON_TYPE,
    LOCAL_PLAN: PATH_TYPE,
    MARKERS: MARKERS_TYPE,
}
#: throttle_rate per layer (ms): a global costmap is big and slow to change; the footprint follows the chair
THROTTLE_MS = {GLOBAL: 2000, LOCAL: 500, FOOTPRINT: 100, LOCAL_PLAN: 200, MARKERS: 200}
UPDATES_THROTTLE_MS = 0  # patches build on each other: none may be dropped
MAX_MARKER_TOPICS = 4
RELOOK_S = 5.0


class CostmapUpdateOutside(PmkError):
    """An OccupancyGridUpdate patch does not fit the costmap it updates (the costmap was resized or
    replaced meanwhile: the next full costmap brings it back). Attributes: ``patch`` (x, y, width,
    height) and ``size`` (width, height) of the costmap."""

    def __init__(self, patch: tuple[int, int, int, int], size: tuple[int, int]) -> None:
        super().__init__(f"costmap update {patch} (x, y, width, height) is outside the {size[0]} x {size[1]} costmap")
        self.patch = patch
        self.size = size


class BadLayerMessage(PmkError):
    """A layer's message does not have the shape of its type. Attributes: ``layer``, ``field``."""

    def __init__(self, layer: str, field_name: str, detail: str) -> None:
        super().__init__(f"{layer} message: {field_name} {detail}")
        self.layer = layer
        self.field = field_name


@dataclass(frozen=True)
class Costmap:
    """A costmap: ``data`` int8 (height, width), row 0 = bottom; ``origin`` (x, y, yaw) of cell (0, 0)'s
    corner in ``frame``; ``version`` counts the changes (a full costmap or a patch) since subscribing."""

    data: np.ndarray
    resolution: float
    origin: tuple[float, float, float]
    frame: str
    topic: str
    version: int = 0


@dataclass(frozen=True)
class Footprint:
    """The chair's outline: ``points`` (n, 2) in ``frame``."""

    points: np.ndarray
    frame: str
    topic: str


def _num(value: Any, layer: str, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise BadLayerMessage(layer, name, f"is not a finite number: {value!r}")
    return float(value)


def _dict(value: Any) -> dict[str, Any]:
    """``value`` if it is a JSON object, else an empty one (a missing field reads as its defaults)."""
    return value if isinstance(value, dict) else {}


def _frame(msg: dict[str, Any], default: str) -> str:
    header = msg.get("header")
    frame = header.get("frame_id") if isinstance(header, dict) else None
    return normalise_frame(str(frame)) if frame else default


def parse_costmap(msg: dict[str, Any], topic: str) -> Costmap:
    """A nav_msgs/OccupancyGrid as JSON -> :class:`Costmap`.

    Raises:
        BadLayerMessage: no size, resolution or origin, or data of another length than width x height.
    """
    info = msg.get("info") if isinstance(msg, dict) else None
    if not isinstance(info, dict):
        raise BadLayerMessage(topic, "info", "is missing")
    width, height = (
        int(_num(info.get("width"), topic, "info.width")),
        int(_num(info.get("height"), topic, "info.height")),
    )
    resolution = _num(info.get("resolution"), topic, "info.resolution")
    origin = _dict(info.get("origin"))
    pos = _dict(origin.get("position"))
    data = msg.get("data")
    cells = np.asarray(data if isinstance(data, list) else [], dtype=np.int16)
    if width < 0 or height < 0 or cells.size != width * height or resolution <= 0:
        raise BadLayerMessage(topic, "data", f"has {cells.size} cells for {width} x {height} at {resolution} m")
    pose = (_num(pos.get("x", 0.0), topic, "origin.x"), _num(pos.get("y", 0.0), topic, "origin.y"))
    yaw = yaw_from_quaternion(origin.get("orientation"))
    grid = np.clip(cells, -1, 100).astype(np.int8).reshape(height, width)
    return Costmap(grid, resolution, (*pose, yaw), _frame(msg, "map"), topic)


def same_costmap(a: Costmap, b: Costmap) -> bool:
    """Whether two costmaps draw the same picture (cells, place, frame, topic)."""
    return (a.resolution, a.origin, a.frame, a.topic) == (b.resolution, b.origin, b.frame, b.topic) and (
        a.data.shape == b.data.shape and bool(np.array_equal(a.data, b.data))
    )


def apply_update(costmap: Costmap, msg: dict[str, Any]) -> Costmap:
    """``costmap`` with a map_msgs/OccupancyGridUpdate patch applied (a new value; the old is untouched;
    ``costmap`` itself when the patch changes no cell).

    Raises:
        CostmapUpdateOutside: the patch does not fit; BadLayerMessage: it is malformed.
    """
    x, y = int(_num(msg.get("x"), costmap.topic, "x")), int(_num(msg.get("y"), costmap.topic, "y"))
    w, h = int(_num(msg.get("width"), costmap.topic, "width")), int(_num(msg.get("height"), costmap.topic, "height"))
    data = msg.get("data")
    patch = np.asarray(data if isinstance(data, list) else [], dtype=np.int16)
    rows, cols = costmap.data.shape
    if min(x, y, w, h) < 0 or x + w > cols or y + h > rows or patch.size != w * h:
        raise CostmapUpdateOutside((x, y, w, h), (cols, rows))
    cells = np.clip(patch, -1, 100).astype(np.int8).reshape(h, w)
    if np.array_equal(costmap.data[y : y + h, x : x + w], cells):
        return costmap  # Nav2 sends the window it updated, changed or not: nothing new to draw (or send)
    out = costmap.data.copy()
    out[y : y + h, x : x + w] = cells
    return Costmap(out, costmap.resolution, costmap.origin, costmap.frame, costmap.topic, costmap.version + 1)


def _xy(points: Any) -> np.ndarray:
    xy = [
        (float(p.get("x", 0.0)), float(p.get("y", 0.0)))
        for p in (points if isinstance(points, list) else [])
        if isinstance(p, dict)
    ]
    arr = np.array(xy, dtype=np.float64).reshape(-1, 2)
    return arr[np.isfinite(arr).all(axis=1)]


def parse_footprint(msg: dict[str, Any], topic: str) -> Footprint:
    """A geometry_msgs/PolygonStamped as JSON -> :class:`Footprint` (non-finite points dropped)."""
    polygon = msg.get("polygon") if isinstance(msg, dict) else None
    points = polygon.get("points") if isinstance(polygon, dict) else None
    return Footprint(_xy(points), _frame(msg, "base_link"), topic)


ADD, MODIFY, DELETE, DELETEALL = 0, 1, 2, 3


@dataclass(frozen=True)
class MarkerChange:
    """One Marker of an array: ``action`` (ADD/MODIFY, DELETE, DELETEALL), its key and, to add, the shape."""

    action: int
    key: tuple[str, str, int]  # (topic, namespace, id)
    frame: str
    marker: PlanarMarker | None


def _colour(value: Any) -> tuple[float, float, float, float]:
    c = value if isinstance(value, dict) else {}
    return (float(c.get("r", 1.0)), float(c.get("g", 1.0)), float(c.get("b", 1.0)), float(c.get("a", 1.0)))


def parse_markers(msg: dict[str, Any], topic: str) -> list[MarkerChange]:
    """A visualization_msgs/MarkerArray as JSON -> its changes in order (malformed markers skipped)."""
    out: list[MarkerChange] = []
    markers = msg.get("markers") if isinstance(msg, dict) else None
    for m in markers if isinstance(markers, list) else []:
        if not isinstance(m, dict):
            continue
        action, key = int(m.get("action", ADD) or 0), (topic, str(m.get("ns", "")), int(m.get("id", 0) or 0))
        if action in (DELETE, DELETEALL):
            out.append(MarkerChange(action, key, "", None))
            continue
        pose = _dict(m.get("pose"))
        pos = _dict(pose.get("position"))
        scale = _dict(m.get("scale"))
        try:
            shape = PlanarMarker(
                kind=int(m.get("type", 0) or 0),
                pose=(float(pos.get("x", 0.0)), float(pos.get("y", 0.0)), yaw_from_quaternion(pose.get("orientation"))),
                scale=(float(scale.get("x", 0.0)), float(scale.get("y", 0.0)), float(scale.get("z", 0.0))),
                rgba=_colour(m.get("color")),
                points=_xy(m.get("points")),
                text=str(m.get("text") or ""),
            )
        except (TypeError, ValueError):
            continue
        out.append(MarkerChange(ADD, key, _frame(m, "map"), shape))
    return out


@dataclass
class MarkerBoard:
    """The markers shown now, by (topic, namespace, id), as the arrays' ADD / DELETE / DELETEALL say."""

    shown: dict[tuple[str, str, int], tuple[str, PlanarMarker]] = field(default_factory=dict)
    version: int = 0

    def apply(self, changes: Iterable[MarkerChange]) -> None:
        for change in changes:
            if change.action == DELETEALL:
                self.shown = {k: v for k, v in self.shown.items() if k[0] != change.key[0]}
            elif change.action == DELETE:
                self.shown.pop(change.key, None)
            elif change.marker is not None:
                self.shown[change.key] = (change.frame, change.marker)
        self.version += 1


def pick_topics(found: dict[str, list[str]]) -> dict[str, tuple[str, ...]]:
    """Each layer's topics among ``found`` ({type: topics of it}), by Nav2's and move_base's names."""
    grids = found.get(GRID_TYPE, [])
    polygons = found.get(POLYGON_TYPE, [])
    paths = found.get(PATH_TYPE, [])
    published = [t for t in polygons if t.endswith("local_costmap/published_footprint")]
    footprints = published or [t for t in polygons if t.endswith("local_costmap/footprint")]
    footprints = footprints or [t for t in polygons if "footprint" in t]
    return {
        GLOBAL: tuple(t for t in grids if t.endswith("global_costmap/costmap"))[:1],
        LOCAL: tuple(t for t in grids if t.endswith("local_costmap/costmap"))[:1],
        FOOTPRINT: tuple(footprints[:1]),
        LOCAL_PLAN: tuple(t for t in paths if t.endswith("local_plan"))[:1],
        MARKERS: tuple(sorted(found.get(MARKERS_TYPE, [])))[:MAX_MARKER_TOPICS],
    }


class NavLayerWatch:
    """Finds the layers' topics and follows those switched on, on a link's ``roslibpy.Ros``.

    ``want(layer, on)`` from the page; ``follow(ros)`` from a screen's timer with the link's current
    Ros (None when disconnected); the ``latest_*`` readers are safe from any thread.
    """

    def __init__(self, lookup: Callable[[str], list[str]], relook_s: float = RELOOK_S) -> None:
        """``lookup``: topics of a message type (``link.topics_of_type``: rosapi's topics_for_type)."""
        self._lookup = lookup
        self._relook_s = relook_s
        self._lock = threading.Lock()
        self._ros: roslibpy.Ros | None = None
        self._wanted: set[str] = set()
        self._found: dict[str, tuple[str, ...]] | None = None
        self._updates: set[str] = set()
        self._looked: float | None = None
        self._looking = False
        self._subs: dict[str, list[OwnSubscription]] = {}
        self._costmaps: dict[str, Costmap] = {}
        self._footprint: Footprint | None = None
        self._plan: PlannedPath | None = None
        self._board = MarkerBoard()
        self.counts = dict.fromkeys(LAYERS, 0)
        #: patches applied per layer (``counts`` counts only those that changed a cell)
        self.patches = dict.fromkeys(LAYERS, 0)
        self.errors = 0

    # -- readers -------------------------------------------------------------------------------------
    def costmap(self, layer: str) -> Costmap | None:
        with self._lock:
            return self._costmaps.get(layer)

    def footprint(self) -> Footprint | None:
        with self._lock:
            return self._footprint

    def local_plan(self) -> PlannedPath | None:
        with self._lock:
            return self._plan

    def markers(self) -> tuple[int, list[tuple[str, PlanarMarker]]]:
        """(version, [(frame, marker)]) of the markers shown now."""
        with self._lock:
            return self._board.version, list(self._board.shown.values())

    def topics(self) -> dict[str, tuple[str, ...]]:
        """Each layer's topics found (empty before the first lookup answered)."""
        with self._lock:
            return dict(self._found or {})

    @property
    def subscribed(self) -> dict[str, tuple[str, ...]]:
        with self._lock:
            return {layer: tuple(s.topic for s in subs) for layer, subs in self._subs.items() if subs}

    # -- control ---------------------------------------------------------------------------------------
    def want(self, layer: str, on: bool) -> None:
        """Show ``layer`` or not (unknown names are refused with ValueError); takes effect at ``follow``."""
        if layer not in LAYERS:
            raise ValueError(f"unknown layer {layer!r}; known: {', '.join(LAYERS)}")
        with self._lock:
            (self._wanted.add if on else self._wanted.discard)(layer)

    def follow(self, ros: roslibpy.Ros | None) -> None:
        """Bring the subscriptions in line with the wanted layers on ``ros``; look the topics up (on a
        thread of its own) when a wanted layer has none and the last lookup is ``relook_s`` old."""
        if ros is not self._ros:
            self.stop()
            if ros is None:
                return
            with self._lock:
                self._ros, self._looked, self._found = ros, None, None
        if ros is None:
            return
        now = time.monotonic()
        with self._lock:
            wanted, found = set(self._wanted), self._found
            missing = any(not (found or {}).get(layer) for layer in wanted)
            stale = self._looked is None or now - self._looked >= self._relook_s
            due = bool(wanted) and missing and stale and not self._looking
            if due:
                self._looking, self._looked = True, now
        if due:
            threading.Thread(target=self._look_up, args=(ros,), name="pmk-navlayers-lookup", daemon=True).start()
        self._sync(ros)

    def _look_up(self, ros: roslibpy.Ros) -> None:
        found: dict[str, list[str]] = {}
        try:
            for type_name in (*dict.fromkeys(LAYER_TYPES.values()), UPDATE_TYPE):
                found[type_name] = list(self._lookup(type_name))
        except PmkError as err:  # no rosapi, busy, reconnecting: nothing is guessed; asked again later
            log.info("looking up the navigation layers' topics failed: %s", err)
            found = {}
        with self._lock:
            self._looking = False
            if ros is not self._ros or not found:
                return
            self._found = pick_topics(found)
            self._updates = set(found.get(UPDATE_TYPE, []))
        self._sync(ros)

    def _sync(self, ros: roslibpy.Ros) -> None:
        ended: list[OwnSubscription] = []
        with self._lock:
            if ros is not self._ros:
                return
            for layer in LAYERS:
                topics = (self._found or {}).get(layer, ()) if layer in self._wanted else ()
                subs = self._subs.get(layer, [])
                if topics and not subs:
                    self._subs[layer] = self._subscribe(ros, layer, topics, OwnSubscription)
                elif not topics and subs:
                    ended += subs
                    self._subs[layer] = []
                    self._forget(layer)
        for sub in ended:
            sub.stop()

    def _subscribe(
        self, ros: roslibpy.Ros, layer: str, topics: tuple[str, ...], make: type[OwnSubscription]
    ) -> list[OwnSubscription]:
        subs = [
            make(ros, t, LAYER_TYPES[layer], functools.partial(self._on_message, layer, t), THROTTLE_MS[layer])
            for t in topics
        ]
        if layer in (GLOBAL, LOCAL):
            subs += [
                make(ros, f"{t}_updates", UPDATE_TYPE, functools.partial(self._on_update, layer), UPDATES_THROTTLE_MS)
                for t in topics
                if f"{t}_updates" in self._updates
            ]
        return subs

    def _forget(self, layer: str) -> None:  # under the lock
        self._costmaps.pop(layer, None)
        if layer == FOOTPRINT:
            self._footprint = None
        elif layer == LOCAL_PLAN:
            self._plan = None
        elif layer == MARKERS:
            self._board = MarkerBoard(version=self._board.version + 1)

    def stop(self) -> None:
        """Unsubscribe everything (the layers wanted stay wanted for the next ``follow``)."""
        with self._lock:
            subs = [s for layer_subs in self._subs.values() for s in layer_subs]
            self._subs, self._ros = {}, None
            for layer in LAYERS:
                self._forget(layer)
        for sub in subs:
            sub.stop()

    # -- the I/O thread: parse and store ---------------------------------------------------------------------
    def _on_message(self, layer: str, topic: str, msg: dict[str, Any]) -> None:
        try:
            if layer in (GLOBAL, LOCAL):
                costmap = parse_costmap(msg, topic)
                with self._lock:
                    old = self._costmaps.get(layer)
                if old is not None and same_costmap(old, costmap):
                    pass  # republished unchanged (a global costmap every few seconds): nothing to draw again
                else:
                    with self._lock:
                        self._costmaps[layer] = replace(costmap, version=old.version + 1 if old else 1)
            elif layer == FOOTPRINT:
                footprint = parse_footprint(msg, topic)
                with self._lock:
                    self._footprint = footprint
            elif layer == LOCAL_PLAN:
                path = parse_path(msg, topic, time.monotonic())
                with self._lock:
                    self._plan = path
            else:
                changes = parse_markers(msg, topic)
                with self._lock:
                    self._board.apply(changes)
        except PmkError as err:
            self.errors += 1
            log.info("%s", err)
            return
        with self._lock:
            self.counts[layer] += 1

    def _on_update(self, layer: str, msg: dict[str, Any]) -> None:
        with self._lock:
            old = self._costmaps.get(layer)
        if old is None:
            return  # a patch before its costmap: the full one comes first once subscribed
        try:
            new = apply_update(old, msg)
        except PmkError as err:
            self.errors += 1
            log.info("%s", err)
            return
        with self._lock:
            self.patches[layer] += 1
            if self._costmaps.get(layer) is old and new is not old:
                self._costmaps[layer] = new
                self.counts[layer] += 1
