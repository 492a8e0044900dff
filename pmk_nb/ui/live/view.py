"""The live preview canvas: the map, the chair, its heading/velocity and the laser scan (ipycanvas).

Two layers in a ``MultiCanvas``: the map layer (:mod:`pmk_nb.ui.live.map_layer`) shows the grid
at screen resolution from a tile that is re-rendered only on a zoom, a new map, a new client or
when the view leaves it, and merely moved while the view follows the chair; the dynamic layer
(:mod:`pmk_nb.ui.live.chair_layer`) is cleared and redrawn every frame with batched calls, all in
one ``hold_canvas`` so a frame is one comm message.  A :class:`RenderLoop` draws at most ``fps``
frames a second from the *latest* messages the chair link has stored, so a 50 Hz odometry or
40 Hz scan never queues drawing work, and frames whose inputs did not change are skipped.
Zoom comes from the screen's buttons (:meth:`LiveView.zoom_in`), the wheel and pinches; a drag
(mouse or one finger) pans and turns Follow off; the view's own toolbar (:attr:`LiveView.toolbar`)
has Follow and Centre (:mod:`pmk_nb.ui.live.gestures`).  The map shows with or without a chair.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Callable
from typing import Any, Protocol

import ipywidgets as w
import numpy as np
from ipycanvas import MultiCanvas

from pmk_nb.chair import Odometry, Pose2D, Scan
from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.grid import OccupancyGrid
from pmk_nb.ui.live import page_script
from pmk_nb.ui.live.canvas_fix import make_messages_name_their_layer
from pmk_nb.ui.live.chair_layer import LASER_STYLES, ChairLook, PoseHistory, draw_chair_layer
from pmk_nb.ui.live.frame_metrics import FrameMetrics, install_byte_meter, measured_hold
from pmk_nb.ui.live.gestures import LiveToolbar, ZoomGestures
from pmk_nb.ui.live.map_layer import TILE_MARGIN, MapLayer
from pmk_nb.ui.live.page_feed import PageFeed
from pmk_nb.ui.live.render_loop import RenderLoop
from pmk_nb.viewport import Insets, Viewport, fit_canvas

RAY_SPACING_PX = 2.0  # thin out rays that would end closer than this on screen
#: Frame-rate cap: a little above the 30 fps the page must draw, so timer jitter on a busy kernel
#: never takes it below (frames whose inputs did not change are skipped anyway).
DEFAULT_FPS = 32.0
#: With the page drawing the chair (issue 41): the kernel's own frames (map, laser, overlays) at most
#: this often on Home, and the chair's poses to the page up to FEED_HZ (each a few hundred bytes, a
#: canvas frame several kilobytes): the page interpolates, so fewer kernel frames cost no smoothness.
PAGE_CANVAS_FPS = 24.0
FEED_HZ = 50.0
#: After a canvas resize the page may apply the new size after the first frame's drawing (size and
#: drawing travel on different comms) and that frame would be wiped: send everything again this late.
RESIZE_RESEND_S = 0.5
#: The largest canvas a page may ask for (fit_page): a big tablet's map area, one canvas pixel per CSS px.
PAGE_MAX = (1600, 1200)


def drawn_same(
    pose: object,
    odom: object,
    scan: object,
    last_pose: object,
    last_odom: object,
    last_scan: object,
) -> bool:
    """Whether pose, odometry and scan draw what the last frame's did: the pose's place, the velocity
    dot's speeds, the scan's rays (a parked chair's new scans with the same rays draw nothing new: its
    stamp moves the rays only while the chair moves, and then the pose differs anyway)."""

    def place(p: object) -> tuple[object, ...] | None:
        return None if p is None else (p.x, p.y, p.theta, getattr(p, "frame", None))  # type: ignore[attr-defined]

    def speeds(o: object) -> tuple[object, ...] | None:
        return None if o is None else (*place(o), o.v, o.w)  # type: ignore[attr-defined, misc]

    if place(pose) != place(last_pose) or speeds(odom) != speeds(last_odom):
        return False
    if scan is last_scan:
        return True
    if not isinstance(scan, Scan) or not isinstance(last_scan, Scan):
        return False
    a, b = scan, last_scan
    return (
        (a.angle_min, a.angle_increment, a.range_max, a.mount) == (b.angle_min, b.angle_increment, b.range_max, b.mount)
        and np.array_equal(a.ranges, b.ranges, equal_nan=True)
        and np.array_equal(a.at_max, b.at_max)
        and np.array_equal(a.kinds, b.kinds)  # type: ignore[arg-type]
    )


class LiveSource(Protocol):
    """What the live view reads: the chair link's latest messages (never blocking)."""

    def latest_pose(self) -> Pose2D | None: ...
    def latest_odom(self) -> Odometry | None: ...
    def latest_scan(self) -> Scan | None: ...


class Overlay(Protocol):
    """Something drawn over the chair layer every frame (see :attr:`LiveView.overlays`)."""

    version: int

    def draw(self, layer: Any, view: Viewport) -> None: ...


class MapOverlay(Overlay, Protocol):
    """An overlay that depends only on the view and itself (a scale bar, a grid, tapped marks): drawn
    on the map layer when the map is repainted or its ``version`` changes, not every frame
    (see :attr:`LiveView.map_overlays`)."""


class LiveView:
    """The live map canvas with zoom (buttons, wheel, pinch) and follow.

    Args:
        width, height: canvas size in pixels.
        fps: frame-rate cap of the render loop.
        footprint_radius: chair radius in metres (the blue circle).
        zoom_step, max_zoom: see :class:`pmk_nb.viewport.Viewport`.
        show_laser: draw the laser scan.
        fit_to_map: treat ``width`` x ``height`` as the largest size and give the canvas the shape
            of each map set (no empty band around the map at zoom level 1).
        laser_style: "points" (hit dots over a light free-space polygon) or "rays" (one line per ray).
        map_mode: "tile" (the grid at screen resolution, every wall kept) or "nearest" (one cell
            per pixel, re-sent on every pan: the earlier look, kept for comparisons).
        tile_margin: spare map around the view in the tile, in canvas sizes.
        clock: the render loop's pacing, the repaint after a resize, a frame's age (a ``VirtualClock``
            in tests; the messages' ``received`` stamps are on the same clock).
        page_chair: the page draws the chair at its display's rate, interpolated between the poses
            the kernel sends (:mod:`pmk_nb.ui.live.page_feed`); the kernel's frames then carry the
            map, the laser and the overlays only. :attr:`page_widget` must be shown with the canvas.
    """

    def __init__(
        self,
        width: int = 800,
        height: int = 600,
        *,
        fps: float = DEFAULT_FPS,
        footprint_radius: float = 0.35,
        zoom_step: float = 1.5,
        max_zoom: int = 8,
        show_laser: bool = True,
        fit_to_map: bool = False,
        laser_style: str = "points",
        map_mode: str = "tile",
        tile_margin: float = TILE_MARGIN,
        clock: Clock = MONOTONIC,
        page_chair: bool = False,
    ) -> None:
        if laser_style not in LASER_STYLES:
            raise ValueError(f"laser_style must be one of {LASER_STYLES}, got {laser_style!r}")
        self.canvas = MultiCanvas(2, width=int(width), height=int(height))
        self.canvas.layout.max_width = "100%"
        self.canvas.add_class("pmk-live-canvas")
        make_messages_name_their_layer(self.canvas)
        install_byte_meter(self.canvas)
        self.max_size = (int(width), int(height))
        self.fit_to_map = bool(fit_to_map)
        self._resend_at: float | None = None
        self._page_size: tuple[int, int] | None = None  # the page's room for the map (fit_page)
        self.poses = PoseHistory()
        self.map_layer = self.canvas[0]
        self.dyn_layer = self.canvas[1]
        self.map = MapLayer(self.map_layer, self.max_size, margin=tile_margin, mode=map_mode)
        self.laser_style = laser_style
        self._lock = threading.RLock()
        self._zoom_step = zoom_step
        self._max_zoom = max_zoom
        self.footprint_radius = float(footprint_radius)
        self.show_laser = bool(show_laser)
        #: set by the screen when the chair's data stopped coming: the chair is drawn grey
        self.stale = False
        self.ray_spacing_px = RAY_SPACING_PX
        self.viewport: Viewport | None = None
        self._grid: OccupancyGrid | None = None
        self._source: LiveSource | None = None
        self._last_inputs: tuple[object, ...] | None = None
        self._force = True
        self._rays = (0, 0)  # (hits, max-range rays) of the last frame drawn
        self._zoom_listeners: list[Callable[[int], None]] = []
        self._error_listeners: list[Callable[[BaseException], None]] = []
        #: drawn over the chair every frame, e.g. the rooms and route (:mod:`pmk_nb.ui.rooms.layer`);
        #: each has ``draw(layer, view)`` and a ``version`` that changes when it has something new
        self.overlays: list[Overlay] = []
        #: drawn on the map layer, under the chair, only when the map is repainted (the view moved,
        #: a zoom, a new page) or one of them has a new ``version``: a turning chair's frames do not
        #: send them again (the scale bar was a third of a classroom frame's kernel time)
        self.map_overlays: list[MapOverlay] = []
        self._map_overlay_key: tuple[object, ...] | None = None
        self.metrics = FrameMetrics()
        self._clock = clock
        self.loop = RenderLoop(self.render_frame, fps, on_error=self._report_error, clock=clock)
        #: the kernel's canvas frames at most this often (the loop ticks faster for the page's feed)
        self.canvas_fps = self.loop.fps
        self._canvas_due = -float("inf")
        self.canvas.on_client_ready(self._on_client_ready)
        self.gestures = ZoomGestures(
            self.canvas, lambda: self.zoom, self.set_zoom, self._pinch_zoom, self.pan, clock=clock
        )
        self.toolbar = LiveToolbar()
        #: the page-drawn chair's feed and script (page_chair), hidden; None when the kernel draws it
        self.feed: PageFeed | None = None
        self.page_widget: w.Box | None = None
        if page_chair:
            self._page_layer()
        self.toolbar.follow.observe(self._on_follow_toggle, names="value")
        self.toolbar.centre.on_click(lambda _b: self.centre())

    def _page_layer(self) -> None:
        """The page draws the chair: the loop ticks up to twice the canvas rate (at most FEED_HZ) to
        send poses, the canvas is drawn at most ``canvas_fps`` times a second.  Below
        PAGE_CANVAS_FPS (a classroom's cap, set to spare two shared cores) the loop keeps its rate
        and the poses ride on its ticks: no more wake-ups than before."""
        from IPython.display import HTML

        if self.canvas_fps >= PAGE_CANVAS_FPS:  # a capped page (the classroom's 11 fps) keeps its ticks
            self.loop.fps = max(self.canvas_fps, min(FEED_HZ, 2.0 * self.canvas_fps))
        self.feed = PageFeed(1.0 / self.loop.fps)
        self.canvas.add_class(f"pmk-live-{self.feed.id}")
        script = w.Output(layout=w.Layout(display="none"))
        script.append_display_data(HTML(page_script.page_html()))
        self.page_widget = w.Box([self.feed.widget, script], layout=w.Layout(display="none"))
        self.page_widget.add_class("pmk-live-page-layer")

    # -- setup ---------------------------------------------------------------------------------------
    def set_map(self, grid: OccupancyGrid) -> None:
        """Show ``grid`` (the same grid object again changes nothing: the view keeps its zoom and pan)."""
        with self._lock:
            if grid is self._grid and self.viewport is not None:
                return
            old = self.viewport
            if self._page_size is not None:
                self._resize(*self._page_size)
            elif self.fit_to_map:
                self._resize(*fit_canvas(int(grid.width), int(grid.height), *self.max_size))
            self.viewport = Viewport.for_grid(
                grid,
                self.canvas.width,
                self.canvas.height,
                zoom_step=self._zoom_step,
                max_zoom=self._max_zoom,
            )
            if old is not None:
                self.viewport.following = old.following
                self.viewport.set_zoom(old.zoom)
            self._grid = grid
            self.map.set_grid(grid)
            self._force = True
        self.request_redraw()

    @property
    def grid(self) -> OccupancyGrid | None:
        """The map shown (None before :meth:`set_map`)."""
        return self._grid

    def _resize(self, width: int, height: int) -> None:
        if (self.canvas.width, self.canvas.height) == (width, height):
            return
        self.canvas.width, self.canvas.height = width, height
        self._resend_at = self._clock.now() + RESIZE_RESEND_S

    def fit_page(self, width: int, height: int) -> bool:
        """Give the canvas the page's room for the map (CSS px, clamped to 160 px .. PAGE_MAX),
        whatever the map's shape: the map screen fills the window (issue 28). True if it changed."""
        size = (min(max(int(width), 160), PAGE_MAX[0]), min(max(int(height), 160), PAGE_MAX[1]))
        with self._lock:
            if size == self._page_size:
                return False
            self._page_size = size
            self.map.fit(size)
            self._resize(*size)
            if self.viewport is not None:
                self.viewport.resize(*size)
            self._force = True
        self.request_redraw()
        return True

    def set_insets(self, insets: Insets) -> None:
        """Panels cover ``insets`` of the canvas: following keeps the chair in the rest."""
        with self._lock:
            if self.viewport is None or self.viewport.insets == insets:
                return
            self.viewport.set_insets(insets)
            self._force = True
        self.request_redraw()

    def chair_pixel(self) -> tuple[float, float] | None:
        """Where the chair is drawn on the canvas, in canvas pixels (None before one was seen)."""
        with self._lock:
            return self.viewport.chair_pixel() if self.viewport is not None else None

    def attach(self, source: LiveSource | None) -> None:
        """Read poses and scans from ``source`` (a ChairLink); None shows the map alone."""
        with self._lock:
            self._source = source
            self.poses.clear()
            if self.feed is not None:
                self.feed.clear()
            if self.viewport is not None:
                self.viewport.forget_chair()  # Centre means the map until a chair is seen again
            self._force = True
        self.request_redraw()  # stopped: the map alone at once, not the last frame's chair

    def start(self, source: LiveSource | None = None) -> str:
        """Start drawing (at most ``fps`` frames/s); returns the loop mode ("asyncio" or "thread")."""
        if source is not None:
            self.attach(source)
        return self.loop.start()

    def stop(self) -> None:
        self.loop.stop()
        with self._lock:
            self._send_feed()  # (page_chair) no more updates are promised: the page must not say "link slow"

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

    # -- pan, follow, centre -------------------------------------------------------------------------
    @property
    def following(self) -> bool:
        return bool(self.toolbar.follow.value)

    def pan(self, dx: float, dy: float) -> None:
        """Move the map by (dx, dy) canvas pixels, as a drag does; turns Follow off."""
        with self._lock:
            if self.viewport is None:
                return
            self.viewport.pan_pixels(dx, dy)
        self._show_following(False)
        self.request_redraw()

    def set_following(self, on: bool) -> None:
        """Follow the chair (centred at once) or leave the view where it is."""
        with self._lock:
            if self.viewport is not None:
                self.viewport.set_following(on)
        self._show_following(bool(on))
        self.request_redraw()

    def centre(self) -> None:
        """Centre on the chair (or on the map when no chair has been seen); Follow stays as it is."""
        with self._lock:
            if self.viewport is not None:
                self.viewport.centre()
        self.request_redraw()

    def _show_following(self, on: bool) -> None:
        if self.toolbar.follow.value != on:
            self.toolbar.follow.value = on  # its observer calls set_following(on): a no-op by then

    def _on_follow_toggle(self, change: dict[str, object]) -> None:
        on = bool(change.get("new"))
        if self.viewport is not None and self.viewport.following != on:
            self.set_following(on)

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
            self.map.invalidate()
            for overlay in self.map_overlays:  # hidden canvases (a costmap's image) are empty there too
                invalidate = getattr(overlay, "invalidate", None)
                if callable(invalidate):
                    invalidate()
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
            view = self.viewport
            if view is None:
                return False
            if self._resend_at is not None and self._clock.now() >= self._resend_at:
                self._resend_at = None
                self._force = True
                self.map.invalidate()
            pose, odom, scan = self._read_source()
            if pose is not None:
                view.see_chair(pose.x, pose.y)
            if odom is not None:
                self.poses.remember(odom)  # by header stamp: where each scan was cast
            if self.feed is not None and pose is not None:
                v = float(odom.v) if odom is not None else 0.0
                self.feed.remember(pose.received, pose.x, pose.y, pose.theta, v)
            key = view.state_key()
            inputs: tuple[object, ...] = (
                key,
                pose,
                odom,
                scan,
                self.show_laser,
                self.footprint_radius,
                self.stale,
                self.laser_style,
            )
            inputs += tuple(o.version for o in self.overlays) + tuple(o.version for o in self.map_overlays)
            # (page_chair) the feed's tick between canvas frames, checked first: it is the cheap test
            if not self._force and (self._clock.now() < self._canvas_due or self._same_inputs(inputs)):
                self.metrics.skipped += 1
                self._send_feed()
                return False
            started = time.perf_counter()
            with measured_hold(self.canvas) as sent:
                draw_map = self._draw_map(view, key)
                self._draw_dynamic(view, pose, odom, scan)
            self._force = False
            self._last_inputs = inputs
            if self.feed is not None:  # under a period: a tick a little early (a busy kernel) still draws
                self._canvas_due = self._clock.now() + 0.75 / self.canvas_fps
                self.feed.drawn(view, self.footprint_radius)
            self.metrics.record(started, self._clock.now(), sent[0], draw_map, pose, odom, scan)
            self.metrics.last_hits, self.metrics.last_max_rays = self._rays
            self._send_feed()
            return True

    def _send_feed(self) -> None:
        """The page-drawn chair's poses, after the frame they go with (page_chair only)."""
        if self.feed is not None:
            self.feed.send(self._clock.now(), self.metrics.frames, self.stale, running=self.loop.running)

    def scan_pose(self, pose: Pose2D | Odometry, scan: Scan) -> tuple[float, float, float]:
        """Where the rays start: ``pose`` moved back to the scan's header stamp by the odometry since
        (:class:`~pmk_nb.ui.live.chair_layer.PoseHistory`), else ``pose``."""
        return self.poses.scan_pose(pose, scan)

    def _same_inputs(self, inputs: tuple[object, ...]) -> bool:
        last = self._last_inputs
        if last is None:
            return False
        key, pose, odom, scan, *rest = inputs
        last_key, last_pose, last_odom, last_scan, *last_rest = last
        # compared by what is drawn, not by message: a parked chair's 20 Hz odometry and unchanged
        # scans draw the same frame again (a classroom page redrew it 12 times a second for nothing)
        return key == last_key and rest == last_rest and drawn_same(pose, odom, scan, last_pose, last_odom, last_scan)

    def _draw_map(self, view: Viewport, key: object) -> bool:
        """The map layer, and the map overlays on it when it was repainted or they changed; True when
        a new map image was sent."""
        overlay_key = (key, *(o.version for o in self.map_overlays))
        if overlay_key != self._map_overlay_key and self.map_overlays:
            self.map.repaint()
        rendered = self.map.draw(view)
        if self.map.repainted:
            for overlay in self.map_overlays:
                overlay.draw(self.map_layer, view)
        self._map_overlay_key = overlay_key
        return rendered

    def _draw_dynamic(
        self, view: Viewport, pose: Pose2D | Odometry | None, odom: Odometry | None, scan: Scan | None
    ) -> None:
        """The dynamic layer (a method so a subclass, e.g. the benchmark's, can draw more on it)."""
        look = ChairLook(
            self.footprint_radius, self.stale, self.ray_spacing_px, self.laser_style, chair=self.feed is None
        )
        self._rays = draw_chair_layer(self.dyn_layer, view, pose, odom, scan, look, self.poses)
        for overlay in self.overlays:
            overlay.draw(self.dyn_layer, view)

    def close(self) -> None:
        self.stop()
        with self._lock:
            self._source = None
        self.canvas.close()
