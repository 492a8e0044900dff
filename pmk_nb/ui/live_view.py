"""The live preview canvas: the map, the chair, its heading/velocity and the laser scan (ipycanvas).

Two layers in a ``MultiCanvas``: the map layer is a NumPy crop of the map image (nearest
neighbour, canvas size) sent with ``put_image_data`` only when the view changes (zoom, a pan of
at least one pixel, a new map, a new client); the dynamic layer is cleared and redrawn every frame
with batched calls (one ``stroke_line_segments`` per ray kind, one ``fill_styled_circles``), all in
one ``hold_canvas`` so a frame is one comm message.  A :class:`RenderLoop` draws at most ``fps``
frames a second from the *latest* messages the chair link has stored, so a 50 Hz odometry or 40 Hz
scan never queues drawing work, and frames whose inputs did not change are skipped.
"""

from __future__ import annotations

import contextlib
import logging
import math
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any, Protocol

import numpy as np
from ipycanvas import MultiCanvas

from pmk_nb.ui.frame_metrics import FrameMetrics, measured_hold
from pmk_nb.ui.render_loop import RenderLoop
from pmk_nb.viewport import Viewport, fit_canvas, heading_point, laser_segments

log = logging.getLogger(__name__)

CHAIR_RGB = (31, 111, 235)  # blue
HEADING_RGB = (245, 196, 0)  # yellow
STALE_RGB = (140, 140, 140)  # grey: the last known pose, no fresh data
HIT_STYLE = "rgba(220, 20, 20, 0.6)"  # red: the ray ended on an obstacle
MAX_STYLE = "rgba(220, 20, 20, 0.15)"  # faint red: nothing seen up to the sensor's range
RAY_SPACING_PX = 2.0  # thin out rays that would end closer than this on screen
WHEEL_INTERVAL = 0.15  # s between two wheel zoom steps (trackpads send bursts of events)
#: After a canvas resize the page may apply the new size after the first frame's drawing (size and
#: drawing travel on different comms) and that frame would be wiped: send everything again this late.
RESIZE_RESEND_S = 0.5
#: Rays are drawn from the pose the chair had when the scan arrived, if one seen is this close in
#: time; the newest pose otherwise.  A turning chair's scan drawn from the newer heading would
#: show rays going through walls (38 deg/s x 0.1 s = 4 deg, half a metre at 8 m).
SCAN_POSE_MATCH_S = 0.25


class LiveSource(Protocol):
    """What the live view reads: the chair link's latest messages (never blocking)."""

    def latest_pose(self) -> Any: ...
    def latest_odom(self) -> Any: ...
    def latest_scan(self) -> Any: ...


def _pose_tuple(pose: Any) -> tuple[float, ...] | None:
    if pose is None:
        return None
    return (float(pose.x), float(pose.y), float(pose.theta), float(getattr(pose, "received", 0.0)))


class LiveView:
    """The live map canvas with zoom (buttons, wheel, pinch) and follow.

    Args:
        width, height: canvas size in pixels.
        fps: frame-rate cap of the render loop.
        footprint_radius: chair radius in metres (the blue circle).
        zoom_step, max_zoom: see :class:`pmk_nb.viewport.Viewport`.
        show_laser: draw the scan rays.
        fit_to_map: treat ``width`` x ``height`` as the largest size and give the canvas the shape
            of each map set (no empty band around the map at zoom level 1).
    """

    def __init__(
        self,
        width: int = 800,
        height: int = 600,
        *,
        fps: float = 20.0,
        footprint_radius: float = 0.35,
        zoom_step: float = 1.5,
        max_zoom: int = 8,
        show_laser: bool = True,
        fit_to_map: bool = False,
    ) -> None:
        self.canvas = MultiCanvas(2, width=int(width), height=int(height))
        self.canvas.layout.max_width = "100%"
        self.canvas.add_class("pmk-live-canvas")
        self.max_size = (int(width), int(height))
        self.fit_to_map = bool(fit_to_map)
        self._resend_at: float | None = None
        self._pose_hist: deque[tuple[float, ...]] = deque(maxlen=32)  # (x, y, theta, received)
        self.map_layer = self.canvas[0]
        self.dyn_layer = self.canvas[1]
        self._lock = threading.RLock()
        self._zoom_step = zoom_step
        self._max_zoom = max_zoom
        self.footprint_radius = float(footprint_radius)
        self.show_laser = bool(show_laser)
        #: set by the screen when the chair's data stopped coming: the chair is drawn grey
        self.stale = False
        self.ray_spacing_px = RAY_SPACING_PX
        self.viewport: Viewport | None = None
        self._gray: np.ndarray | None = None
        self._source: LiveSource | None = None
        self._map_key: tuple[object, ...] | None = None
        self._last_inputs: tuple[object, ...] | None = None
        self._force = True
        self._last_recorded: tuple[Any, Any] = (None, None)
        self._hits = self._max_rays = 0
        self._zoom_listeners: list[Callable[[int], None]] = []
        self._error_listeners: list[Callable[[BaseException], None]] = []
        self._pinch: tuple[float, int] | None = None
        self._last_wheel = 0.0
        self.metrics = FrameMetrics()
        self.loop = RenderLoop(self.render_frame, fps, on_error=self._report_error)
        self.canvas.on_client_ready(self._on_client_ready)
        self.canvas.on_mouse_wheel(self._on_wheel)
        self.canvas.on_touch_start(self._on_touch)
        self.canvas.on_touch_move(self._on_touch)
        self.canvas.on_touch_end(self._on_touch_end)
        self.canvas.on_touch_cancel(self._on_touch_end)

    # -- setup ---------------------------------------------------------------------------------------
    def set_map(self, grid: Any, gray: np.ndarray | None = None) -> None:
        """Show ``grid`` (an OccupancyGrid); ``gray`` is its uint8 image (row 0 = top) if already made."""
        if gray is None:
            from pmk_nb.rosmap.files import grid_to_gray

            gray = grid_to_gray(grid)
        with self._lock:
            if self.fit_to_map:
                self._resize(*fit_canvas(int(grid.width), int(grid.height), *self.max_size))
            zoom = self.viewport.zoom if self.viewport is not None else 1
            self.viewport = Viewport.for_grid(
                grid,
                self.canvas.width,
                self.canvas.height,
                zoom_step=self._zoom_step,
                max_zoom=self._max_zoom,
            )
            self.viewport.set_zoom(zoom)
            self._gray = np.ascontiguousarray(gray, dtype=np.uint8)
            self._map_key = None
            self._force = True
        self.request_redraw()

    def _resize(self, width: int, height: int) -> None:
        if (self.canvas.width, self.canvas.height) == (width, height):
            return
        self.canvas.width, self.canvas.height = width, height
        self._resend_at = time.monotonic() + RESIZE_RESEND_S

    def attach(self, source: LiveSource | None) -> None:
        """Read poses and scans from ``source`` (a ChairLink); None shows the map alone."""
        with self._lock:
            self._source = source
            self._pose_hist.clear()
            self._force = True

    def start(self, source: LiveSource | None = None) -> str:
        """Start drawing (at most ``fps`` frames/s); returns the loop mode ("asyncio" or "thread")."""
        if source is not None:
            self.attach(source)
        return self.loop.start()

    def stop(self) -> None:
        self.loop.stop()

    @property
    def running(self) -> bool:
        return self.loop.running

    def on_zoom_change(self, cb: Callable[[int], None]) -> None:
        self._zoom_listeners.append(cb)

    def on_error(self, cb: Callable[[BaseException], None]) -> None:
        self._error_listeners.append(cb)

    # -- zoom ----------------------------------------------------------------------------------------
    @property
    def zoom(self) -> int:
        return self.viewport.zoom if self.viewport is not None else 1

    @property
    def zoom_factor(self) -> float:
        return self.viewport.zoom_factor if self.viewport is not None else 1.0

    def set_zoom(self, level: object) -> int:
        """Set the zoom level (clamped); raises ValueError for non-numbers. Returns the level set."""
        with self._lock:
            if self.viewport is None:
                return 1
            before = self.viewport.zoom
            after = self.viewport.set_zoom(level)
        if after != before:
            for cb in list(self._zoom_listeners):
                with contextlib.suppress(Exception):
                    cb(after)
            self.request_redraw()
        return after

    def zoom_in(self) -> int:
        return self.set_zoom(self.zoom + 1)

    def zoom_out(self) -> int:
        return self.set_zoom(self.zoom - 1)

    def _on_wheel(self, dx: object, dy: object) -> None:
        try:
            delta = float(dy)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            return
        now = time.monotonic()
        if not math.isfinite(delta) or delta == 0 or now - self._last_wheel < WHEEL_INTERVAL:
            return
        self._last_wheel = now
        self.set_zoom(self.zoom + (1 if delta < 0 else -1))  # wheel up (negative delta) zooms in

    @staticmethod
    def _pinch_distance(touches: object) -> float | None:
        try:
            (x0, y0), (x1, y1) = list(touches)[:2]  # type: ignore[call-overload]
            d = math.hypot(float(x1) - float(x0), float(y1) - float(y0))
        except (TypeError, ValueError):
            return None
        return d if math.isfinite(d) and d > 0 else None

    def _on_touch(self, touches: object) -> None:
        """Two fingers: the zoom follows the ratio of finger distances since the pinch began."""
        dist = self._pinch_distance(touches)
        if dist is None or self.viewport is None:
            self._pinch = None
            return
        if self._pinch is None:
            self._pinch = (dist, self.zoom)
            return
        start_dist, start_zoom = self._pinch
        self.set_zoom(self.viewport.zoom_for_pinch(start_zoom, dist / start_dist))

    def _on_touch_end(self, touches: object) -> None:
        try:
            fingers = len(list(touches))  # type: ignore[call-overload]
        except TypeError:
            fingers = 0
        if fingers < 2:
            self._pinch = None

    # -- drawing -------------------------------------------------------------------------------------
    def request_redraw(self) -> None:
        """Redraw everything at the next frame (now, if the loop is not running)."""
        with self._lock:
            self._force = True
        if not self.loop.running:
            try:
                self.render_frame()
            except Exception as err:  # keep widget callbacks traceback-free
                self._report_error(err)

    def _on_client_ready(self) -> None:
        # a new page (reload, second view) starts with empty canvases: send both layers again
        with self._lock:
            self._map_key = None
        self.request_redraw()

    def _report_error(self, err: BaseException) -> None:
        self.metrics.errors += 1
        for cb in list(self._error_listeners):
            with contextlib.suppress(Exception):
                cb(err)

    def render_frame(self) -> bool:
        """Draw one frame from the latest messages; returns False when nothing changed (skipped)."""
        with self._lock:
            view, gray, source = self.viewport, self._gray, self._source
            if view is None or gray is None:
                return False
            if self._resend_at is not None and time.monotonic() >= self._resend_at:
                self._resend_at = None
                self._force, self._map_key = True, None
            pose = odom = scan = None
            if source is not None:
                odom = source.latest_odom()
                pose = source.latest_pose() or odom
                scan = source.latest_scan() if self.show_laser else None
            if pose is not None:
                view.follow(pose.x, pose.y)
                self._remember(pose)
            key = view.state_key()
            inputs = (key, pose, odom, scan, self.show_laser, self.footprint_radius, self.stale)
            if not self._force and self._same_inputs(inputs):
                self.metrics.skipped += 1
                return False
            t0 = time.perf_counter()
            draw_map = self._map_key is None or key != self._map_key
            with measured_hold(self.canvas) as sent:
                if draw_map:
                    self._draw_map(view, gray)
                self._draw_dynamic(view, pose, odom, scan)
            t_sent = time.monotonic()
            self._force = False
            self._last_inputs = inputs
            self._map_key = key
            self._record(t0, t_sent, sent[0], draw_map, pose, odom, scan)
            return True

    def _remember(self, pose: Any) -> None:
        tup = _pose_tuple(pose)
        if tup is not None and (not self._pose_hist or self._pose_hist[-1] != tup):
            self._pose_hist.append(tup)

    def scan_pose(self, pose: Any, scan: Any) -> tuple[float, float, float]:
        """Where the rays start: the remembered pose nearest the scan's arrival, else ``pose``."""
        received = float(getattr(scan, "received", math.nan))
        best: tuple[float, ...] | None = None
        if math.isfinite(received) and self._pose_hist:
            best = min(self._pose_hist, key=lambda p: abs(p[3] - received))
            if abs(best[3] - received) > SCAN_POSE_MATCH_S:
                best = None
        if best is None:
            return float(pose.x), float(pose.y), float(pose.theta)
        return best[0], best[1], best[2]

    def _same_inputs(self, inputs: tuple[Any, ...]) -> bool:
        last = self._last_inputs
        if last is None:
            return False
        key, pose, odom, scan, *rest = inputs
        last_key, last_pose, last_odom, last_scan, *last_rest = last
        # the link stores one object per odom/scan message (identity = same message); a pose may be
        # rebuilt on every call (from odometry or tf), so it compares by value
        return (
            key == last_key
            and _pose_tuple(pose) == _pose_tuple(last_pose)
            and odom is last_odom
            and scan is last_scan
            and rest == last_rest
        )

    def _draw_map(self, view: Viewport, gray: np.ndarray) -> None:
        img, inside = view.image_window(gray)
        if not inside.all():  # letterbox: transparent outside the map (RGBA is lossless PNG)
            rgba = np.empty((*img.shape, 4), dtype=np.uint8)
            rgba[..., :3] = img[..., None]
            rgba[..., 3] = np.where(inside, 255, 0)
            img = rgba
        self.map_layer.clear()
        self.map_layer.put_image_data(img, 0, 0)

    def _draw_dynamic(self, view: Viewport, pose: Any, odom: Any, scan: Any) -> None:
        layer = self.dyn_layer
        layer.clear()
        self._hits = self._max_rays = 0
        if pose is None:
            return
        x, y, theta = float(pose.x), float(pose.y), float(pose.theta)
        if scan is not None:
            segs = laser_segments(
                view,
                self.scan_pose(pose, scan),
                float(scan.angle_min),
                float(scan.angle_increment),
                scan.ranges,
                getattr(scan, "at_max", None),
                float(getattr(scan, "range_max", math.nan)),
                min_spacing_px=self.ray_spacing_px,
            )
            layer.line_width = 1
            if segs.max_rays.shape[0]:
                layer.stroke_style = MAX_STYLE
                layer.stroke_line_segments(segs.max_rays)
            if segs.hits.shape[0]:
                layer.stroke_style = HIT_STYLE
                layer.stroke_line_segments(segs.hits)
            self._hits, self._max_rays = segs.hits.shape[0], segs.max_rays.shape[0]
        v = float(getattr(odom, "v", 0.0)) if odom is not None else 0.0
        hx, hy = heading_point(x, y, theta, v, self.footprint_radius)
        px, py = view.world_to_pixel(np.array([x, hx]), np.array([y, hy]))
        radius = view.chair_radius_px(self.footprint_radius)
        layer.fill_styled_circles(
            px.astype(np.float32),
            py.astype(np.float32),
            np.array([radius, view.dot_radius_px(self.footprint_radius)], dtype=np.float32),
            np.array([STALE_RGB if self.stale else CHAIR_RGB, HEADING_RGB], dtype=np.uint8),
        )

    def _record(self, t0: float, t_sent: float, nbytes: int, drew_map: bool, pose: Any, odom: Any, scan: Any) -> None:
        m = self.metrics
        m.frames += 1
        m.map_draws += int(drew_map)
        m.frame_ms.append((time.perf_counter() - t0) * 1000.0)
        m.frame_bytes.append(nbytes)
        m.frame_sent.append(t_sent)
        last_odom, last_scan = self._last_recorded
        if odom is not None and odom is not last_odom:
            m.odom_delay_ms.append((t_sent - float(odom.received)) * 1000.0)
        if scan is not None and scan is not last_scan:
            m.scan_delay_ms.append((t_sent - float(scan.received)) * 1000.0)
        self._last_recorded = (odom, scan)
        m.last_pose = (float(pose.x), float(pose.y), float(pose.theta)) if pose is not None else None
        m.last_hits, m.last_max_rays = self._hits, self._max_rays

    def close(self) -> None:
        self.stop()
        with self._lock:
            self._source = None
        self.canvas.close()
