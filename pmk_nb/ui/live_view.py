"""The live preview canvas: the map, the chair, its heading/velocity and the laser scan (ipycanvas).

Two layers in a ``MultiCanvas``: the map layer (:mod:`pmk_nb.ui.live_map_layer`) is sent only
when the view changes (zoom, a pan of at least one pixel, a new map, a new client); the dynamic
layer (:mod:`pmk_nb.ui.live_chair_layer`) is cleared and redrawn every frame with batched calls,
all in one ``hold_canvas`` so a frame is one comm message.  A :class:`RenderLoop` draws at most
``fps`` frames a second from the *latest* messages the chair link has stored, so a 50 Hz odometry
or 40 Hz scan never queues drawing work, and frames whose inputs did not change are skipped.
Zoom comes from the buttons (:meth:`LiveView.zoom_in`), the wheel and pinches
(:mod:`pmk_nb.ui.live_gestures`).
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Callable
from typing import Protocol

import numpy as np
from ipycanvas import MultiCanvas

from pmk_nb.chair.messages import Odometry, Pose2D, Scan
from pmk_nb.grid import OccupancyGrid
from pmk_nb.ui.canvas_fix import make_messages_name_their_layer
from pmk_nb.ui.frame_metrics import FrameMetrics, install_byte_meter, measured_hold
from pmk_nb.ui.live_chair_layer import ChairLook, PoseHistory, draw_chair_layer, pose_tuple
from pmk_nb.ui.live_gestures import ZoomGestures
from pmk_nb.ui.live_map_layer import draw_map_layer
from pmk_nb.ui.render_loop import RenderLoop
from pmk_nb.viewport import Viewport, fit_canvas

RAY_SPACING_PX = 2.0  # thin out rays that would end closer than this on screen
#: After a canvas resize the page may apply the new size after the first frame's drawing (size and
#: drawing travel on different comms) and that frame would be wiped: send everything again this late.
RESIZE_RESEND_S = 0.5


class LiveSource(Protocol):
    """What the live view reads: the chair link's latest messages (never blocking)."""

    def latest_pose(self) -> Pose2D | None: ...
    def latest_odom(self) -> Odometry | None: ...
    def latest_scan(self) -> Scan | None: ...


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
        make_messages_name_their_layer(self.canvas)
        install_byte_meter(self.canvas)
        self.max_size = (int(width), int(height))
        self.fit_to_map = bool(fit_to_map)
        self._resend_at: float | None = None
        self.poses = PoseHistory()
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
        self._rays = (0, 0)  # (hits, max-range rays) of the last frame drawn
        self._zoom_listeners: list[Callable[[int], None]] = []
        self._error_listeners: list[Callable[[BaseException], None]] = []
        self.metrics = FrameMetrics()
        self.loop = RenderLoop(self.render_frame, fps, on_error=self._report_error)
        self.canvas.on_client_ready(self._on_client_ready)
        self.gestures = ZoomGestures(self.canvas, lambda: self.zoom, self.set_zoom, self._pinch_zoom)

    # -- setup ---------------------------------------------------------------------------------------
    def set_map(self, grid: OccupancyGrid, gray: np.ndarray | None = None) -> None:
        """Show ``grid``; ``gray`` is its uint8 image (row 0 = top) if already made."""
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
            self.poses.clear()
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

    def _pinch_zoom(self, start_zoom: int, ratio: float) -> int | None:
        view = self.viewport
        return view.zoom_for_pinch(start_zoom, ratio) if view is not None else None

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

    def _read_source(self) -> tuple[Pose2D | Odometry | None, Odometry | None, Scan | None]:
        source = self._source
        if source is None:
            return None, None, None
        odom = source.latest_odom()
        pose = source.latest_pose() or odom
        scan = source.latest_scan() if self.show_laser else None
        return pose, odom, scan

    def render_frame(self) -> bool:
        """Draw one frame from the latest messages; returns False when nothing changed (skipped)."""
        with self._lock:
            view, gray = self.viewport, self._gray
            if view is None or gray is None:
                return False
            if self._resend_at is not None and time.monotonic() >= self._resend_at:
                self._resend_at = None
                self._force, self._map_key = True, None
            pose, odom, scan = self._read_source()
            if pose is not None:
                view.follow(pose.x, pose.y)
                self.poses.remember(pose)
            key = view.state_key()
            inputs = (key, pose, odom, scan, self.show_laser, self.footprint_radius, self.stale)
            if not self._force and self._same_inputs(inputs):
                self.metrics.skipped += 1
                return False
            started = time.perf_counter()
            draw_map = self._map_key is None or key != self._map_key
            with measured_hold(self.canvas) as sent:
                if draw_map:
                    draw_map_layer(self.map_layer, view, gray)
                self._draw_dynamic(view, pose, odom, scan)
            self._force = False
            self._last_inputs = inputs
            self._map_key = key
            self.metrics.record(started, time.monotonic(), sent[0], draw_map, pose, odom, scan)
            self.metrics.last_hits, self.metrics.last_max_rays = self._rays
            return True

    def scan_pose(self, pose: Pose2D | Odometry, scan: Scan) -> tuple[float, float, float]:
        """Where the rays start: the remembered pose nearest the scan's arrival, else ``pose``."""
        return self.poses.scan_pose(pose, scan)

    def _same_inputs(self, inputs: tuple[object, ...]) -> bool:
        last = self._last_inputs
        if last is None:
            return False
        key, pose, odom, scan, *rest = inputs
        last_key, last_pose, last_odom, last_scan, *last_rest = last
        # the link stores one object per odom/scan message (identity = same message); a pose may be
        # rebuilt on every call (from odometry or tf), so it compares by value
        return (
            key == last_key
            and pose_tuple(pose) == pose_tuple(last_pose)  # type: ignore[arg-type]
            and odom is last_odom
            and scan is last_scan
            and rest == last_rest
        )

    def _draw_dynamic(
        self, view: Viewport, pose: Pose2D | Odometry | None, odom: Odometry | None, scan: Scan | None
    ) -> None:
        """The dynamic layer (a method so a subclass, e.g. the benchmark's, can draw more on it)."""
        look = ChairLook(self.footprint_radius, self.stale, self.ray_spacing_px)
        self._rays = draw_chair_layer(self.dyn_layer, view, pose, odom, scan, look, self.poses)

    def close(self) -> None:
        self.stop()
        with self._lock:
            self._source = None
        self.canvas.close()
