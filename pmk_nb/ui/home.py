"""Home screen: the current map, Preview / Disconnect, Show sensors, zoom, and the live info panel.

As in the original app (thesis 3.2.5, 4.2.1.1, 5.2.3.1, 5.2.3.4): the current map is the last one
sent to the chair; when it cannot be shown there is a warning and no Preview button; Preview
connects to the chair and starts the live view, Disconnect stops it; "Show sensors" toggles the
laser rays; the zoom buttons sit at the map's upper-right corner; position, heading, speed and zoom
are shown in the information panel and updated live, with a clear "no data" state when odometry
stops.  Like the original's wifi dialog, showing Home checks that the chair answers and warns if not.

The live view draws the map from the map files themselves (YAML + image, exact metres and origin).
A missing ``NAME-visualization.png`` preview image gets a warning but keeps Preview: the image is
only a thumbnail here, and refusing to show the map the chair really uses because its thumbnail is
gone would block the user for nothing.  A missing or unreadable map file hides Preview.

With ``autostart`` (``pmk demo``, kiosks: see :data:`pmk_nb.ui.context.AUTOSTART_ENV`) the preview
starts by itself whenever Home is shown, unless the user pressed Disconnect.
"""

from __future__ import annotations

import contextlib
import logging
import math
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.errors import PmkError
from pmk_nb.ui.home_checks import preview_image_problem, probe_chair
from pmk_nb.ui.home_info import CONNECT_TIMEOUT, connection_state, info_texts
from pmk_nb.ui.home_info import call as _call
from pmk_nb.ui.home_info import note as _note
from pmk_nb.ui.home_info import set_html as _set
from pmk_nb.ui.home_info import subscribe_state as _subscribe_state
from pmk_nb.ui.live_view import LiveView
from pmk_nb.ui.render_loop import RenderLoop
from pmk_nb.ui.widgets import TOUCH_PX, button, escape, heading

if TYPE_CHECKING:
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.ui.context import AppContext, CurrentMap

log = logging.getLogger(__name__)

INFO_HZ = 4.0  # info panel refresh rate: text widgets need no 20 fps
#: Largest live canvas: fits the content area of a 1280 x 800 landscape tablet next to the
#: navigation panel; the canvas takes the map's shape within it and the page scales it down on
#: smaller screens.
CANVAS_MAX = (920, 560)


class HomeScreen:
    """The Home screen; ``widget`` is its content, ``info_widget`` its part of the info panel.

    Args:
        ctx: the session (current map, chair profile, link, notifications).
        canvas_width, canvas_height: largest live view size in pixels (it takes the map's shape).
        fps: frame-rate cap of the live view.
        autostart: start the preview whenever Home is shown (:meth:`on_show`), unless the user
            pressed Disconnect; for demos and kiosks.
    """

    def __init__(
        self,
        ctx: AppContext,
        *,
        canvas_width: int = CANVAS_MAX[0],
        canvas_height: int = CANVAS_MAX[1],
        fps: float = 20.0,
        autostart: bool = False,
    ) -> None:
        self.ctx = ctx
        self.autostart = bool(autostart)
        self._user_stopped = False
        self._probe_gen = 0
        self._lock = threading.RLock()
        self._link: Any = None
        self._unsub_state: Any = None
        self._grid_cache: tuple[tuple[str, float, float], OccupancyGrid] | None = None
        self._connect_error: str | None = None
        self._started_at = 0.0
        self.live = LiveView(canvas_width, canvas_height, fps=fps, fit_to_map=True)
        self.live.on_zoom_change(lambda _z: self.refresh_info())
        self.live.on_error(self._on_live_error)

        self.map_label = w.HTML("")
        self.map_label.add_class("pmk-home-map")
        self.map_note = w.HTML("")
        self.map_note.add_class("pmk-home-map-note")
        self.chair_note = w.HTML("")
        self.chair_note.add_class("pmk-home-chair-note")
        self.warning = w.HTML("")
        self.warning.add_class("pmk-home-warning")
        self.status = w.HTML("")
        self.status.add_class("pmk-home-status")
        self.preview_button = button("Preview", "pmk-home-preview", icon="play", style="success")
        self.disconnect_button = button("Disconnect", "pmk-home-disconnect", icon="stop", style="danger")
        # a toggle button rather than a checkbox: the whole 56 px control is the touch target
        self.sensors = w.ToggleButton(value=True, description="Show sensors", icon="check", tooltip="Laser rays")
        self.sensors.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="160px")
        self.sensors.add_class("pmk-home-sensors")
        self.zoom_in_button = button("", "pmk-home-zoom-in", icon="search-plus", tooltip="Zoom in", width="64px")
        self.zoom_out_button = button("", "pmk-home-zoom-out", icon="search-minus", tooltip="Zoom out", width="64px")
        for btn in (self.zoom_in_button, self.zoom_out_button):
            btn.layout.min_width = f"{TOUCH_PX}px"

        self.preview_button.on_click(self._safe("Starting the preview", lambda _b: self._user_start()))
        self.disconnect_button.on_click(self._safe("Disconnecting", lambda _b: self._user_stop()))
        self.zoom_in_button.on_click(self._safe("Zooming in", lambda _b: self.live.zoom_in()))
        self.zoom_out_button.on_click(self._safe("Zooming out", lambda _b: self.live.zoom_out()))
        self.sensors.observe(self._safe("Toggling sensors", self._on_sensors), names="value")

        self.info_pos = w.HTML("")
        self.info_speed = w.HTML("")
        self.info_zoom = w.HTML("")
        self.info_state = w.HTML("")
        for name, item in (
            ("pos", self.info_pos),
            ("speed", self.info_speed),
            ("zoom", self.info_zoom),
            ("state", self.info_state),
        ):
            item.add_class(f"pmk-home-info-{name}")
        self.info_map = w.HTML("")
        self.info_map.add_class("pmk-home-info-map")
        self.info_widget = w.VBox([self.info_map, self.info_state, self.info_pos, self.info_speed, self.info_zoom])
        self.info_widget.add_class("pmk-home-info")

        # one toolbar row: Preview / Disconnect and Show sensors on the left, zoom at the right end,
        # right above the map's upper-right corner (where the original had them); the box is as
        # wide as the canvas, which has the map's shape, so nothing floats in an empty band
        self.zoom_bar = w.HBox([self.zoom_out_button, self.zoom_in_button], layout=w.Layout(grid_gap="8px"))
        self.zoom_bar.add_class("pmk-home-zoom")
        self.controls = w.HBox(
            [self.preview_button, self.disconnect_button, self.sensors],
            layout=w.Layout(align_items="center", grid_gap="12px"),
        )
        self.toolbar = w.HBox(
            [self.controls, self.zoom_bar],
            layout=w.Layout(justify_content="space-between", align_items="center", width="100%", grid_gap="12px"),
        )
        self.toolbar.add_class("pmk-home-toolbar")
        self.preview_box = w.VBox([self.toolbar, self.live.canvas], layout=w.Layout(align_items="flex-start"))
        self.preview_box.add_class("pmk-home-preview-box")
        title = w.HBox([heading("Home"), self.map_label], layout=w.Layout(align_items="baseline", grid_gap="24px"))
        self.widget = w.VBox([title, self.map_note, self.chair_note, self.warning, self.preview_box, self.status])
        self.widget.add_class("pmk-home")
        self._info_loop = RenderLoop(self.refresh_info, INFO_HZ, on_error=self._on_live_error)
        self._unsub_map = ctx.observe_current_map(self._on_current_map)
        self._set_running(False)
        self.refresh_map()

    # -- public API ----------------------------------------------------------------------------------
    @property
    def running(self) -> bool:
        return self.live.running

    def on_show(self) -> None:
        """Called by the app when Home becomes visible: re-check the map files and the chair.

        With ``autostart`` this starts the preview (which reports an unreachable chair itself);
        otherwise a background probe warns early when the chair does not answer.
        """
        grid = self.refresh_map()
        if self.running:
            return
        if self.autostart and not self._user_stopped and grid is not None and self.ctx.profile() is not None:
            self.start_preview()
            return
        self.check_chair()

    def check_chair(self) -> threading.Thread | None:
        """Probe the chair's rosbridge port in a thread; ``chair_note`` warns when it does not answer."""
        profile = self.ctx.profile()
        with self._lock:
            self._probe_gen += 1
            gen = self._probe_gen
        if profile is None:
            _set(self.chair_note, _note("No wheelchair configured yet: fill in and save the Settings screen."))
            return None
        host, port = profile.host, int(profile.port)

        def probe() -> None:
            problem = probe_chair(host, port)
            with self._lock:
                if gen != self._probe_gen:  # a newer check or a preview start took over
                    return
            message = (
                f"The chair at {host}:{port} does not answer ({problem}). Check that it is switched on, "
                "that this device is on the chair's network, and the Settings screen."
            )
            _set(self.chair_note, _note(message) if problem else "")

        thread = threading.Thread(target=probe, name="pmk-home-probe", daemon=True)
        thread.start()
        return thread

    def _user_start(self) -> None:
        self._user_stopped = False
        self.start_preview()

    def _user_stop(self) -> None:
        self._user_stopped = True  # autostart respects the choice until Preview is pressed again
        self.stop_preview()

    def start_preview(self) -> bool:
        """Load the current map, connect the chair link and start drawing; False (with a warning) if not."""
        if self.running:
            return True
        grid = self.refresh_map()
        if grid is None:
            return False
        try:
            link = self.ctx.link()
        except PmkError as err:
            self._warn(str(err))
            return False
        profile = self.ctx.profile()
        footprint = float(getattr(profile, "footprint_radius", 0.35) or 0.35)
        self.live.footprint_radius = footprint if math.isfinite(footprint) and footprint > 0 else 0.35
        self.live.show_laser = bool(self.sensors.value)
        self.live.set_map(grid)
        with self._lock:
            self._probe_gen += 1  # the preview's own connection reports on the chair from now on
            self._link = link
            self._connect_error = None
            self._started_at = time.monotonic()
            self._unsub_state = _subscribe_state(link, self._on_link_state)
        self._warn("")
        _set(self.chair_note, "")
        self._set_running(True)
        self.live.start(link)
        self._info_loop.start()
        # connecting can take seconds (timeout, DNS): do it off the kernel's main thread so the page
        # stays responsive; the canvas shows the map meanwhile and the chair once data flows
        threading.Thread(target=self._connect, args=(link,), name="pmk-home-connect", daemon=True).start()
        self.refresh_info()
        return True

    def stop_preview(self) -> None:
        """Stop drawing and the chair's streams (the link itself stays open for other screens)."""
        self.live.stop()
        self._info_loop.stop()
        with self._lock:
            link, self._link = self._link, None
            unsub, self._unsub_state = self._unsub_state, None
        if unsub is not None:
            with contextlib.suppress(Exception):
                unsub()
        if link is not None:
            try:
                link.stop_streams()
            except Exception as err:  # the chair may be gone already: nothing to stop
                log.info("stopping streams failed: %s", err)
        self.live.attach(None)
        self._set_running(False)
        if self.ctx.current_map is None or self._grid_cache is None:
            self.preview_button.layout.display = "none"
        self.refresh_info()

    def close(self) -> None:
        self.stop_preview()
        with contextlib.suppress(Exception):
            self._unsub_map()
        self.live.close()

    # -- map -----------------------------------------------------------------------------------------
    def refresh_map(self) -> OccupancyGrid | None:
        """Show the current map's name; load its grid (cached) or warn and hide Preview."""
        current = self.ctx.current_map
        if current is None:
            _set(self.map_note, "")
            self.map_label.value = "<b>No map yet.</b> Convert a map and send it to the chair on the Maps screen."
            self.info_map.value = "Map: <i>none</i>"
            self._map_problem("No current map: send a map to the chair from the Maps screen first.")
            return None
        self.map_label.value = f"Current map: <b>{escape(current.name)}</b>"
        self.info_map.value = f"Map: <b>{escape(current.name)}</b>"
        try:
            grid = self._load_grid(current)
        except (PmkError, OSError, ValueError) as err:
            _set(self.map_note, "")
            self._map_problem(f"The map '{current.name}' cannot be shown: {err}. Convert and send it again.")
            return None
        problem = preview_image_problem(current)
        _set(self.map_note, _note(problem) if problem else "")
        self.preview_button.layout.display = "none" if self.running else ""
        if not self.running:
            self._warn("")
        return grid

    def _load_grid(self, current: CurrentMap) -> OccupancyGrid:
        from pmk_nb.rosmap.files import read_map, read_map_yaml

        yaml_path = Path(current.yaml)
        if not yaml_path.is_file():
            raise FileNotFoundError(f"map file {yaml_path} is missing")
        image = Path(read_map_yaml(yaml_path).image)
        key = (str(yaml_path), yaml_path.stat().st_mtime, image.stat().st_mtime if image.is_file() else -1.0)
        with self._lock:
            if self._grid_cache is not None and self._grid_cache[0] == key:
                return self._grid_cache[1]
        grid = read_map(yaml_path)
        with self._lock:
            self._grid_cache = (key, grid)
        return grid

    def _map_problem(self, message: str) -> None:
        self.preview_button.layout.display = "none"
        self._warn(message)

    def _on_current_map(self, _current: CurrentMap | None) -> None:
        grid = self.refresh_map()
        if self.running and grid is not None:
            self.live.set_map(grid)

    # -- link ----------------------------------------------------------------------------------------
    def _connect(self, link: Any) -> None:
        try:
            link.connect(timeout=CONNECT_TIMEOUT)
            link.start_streams()
        except Exception as err:
            host = getattr(link, "host", "?")
            port = getattr(link, "port", "?")
            where = f"{host}:{port}"
            # the link's message usually names the address already: do not say it twice
            who = "The chair" if where in str(err) else f"The chair at {where}"
            message = f"{who} is unreachable: {err}"
            with self._lock:
                if self._link is not link:  # stopped meanwhile
                    return
                self._connect_error = message
            # no chair, no preview (as the original app): stop, and say why and what to do
            self.stop_preview()
            self._warn(message + " Check the Settings screen and the network, then press Preview again.")
            self.ctx.notify(message, "warning")

    def _on_link_state(self, _state: object) -> None:
        with contextlib.suppress(Exception):
            self.refresh_info()

    def connection_state(self) -> tuple[str, float | None]:
        """("off"|"connecting"|"live"|"stale"|"unreachable", seconds since the last odometry or None)."""
        with self._lock:
            link, error, started = self._link, self._connect_error, self._started_at
        return connection_state(link, error, started)

    # -- info panel ----------------------------------------------------------------------------------
    def refresh_info(self) -> None:
        """Update position, speed, zoom and state texts (only widgets whose text changed are sent)."""
        state, age = self.connection_state()
        link = self._link
        odom = _call(link, "latest_odom") if link is not None else None
        pose = (_call(link, "latest_pose") if link is not None else None) or odom
        texts = info_texts(state, age, pose, odom, self.live.zoom, self.live.zoom_factor)
        self.live.stale = state == "stale"  # the loop redraws: the chair turns grey
        _set(self.info_state, texts.state)
        _set(self.info_pos, texts.position)
        _set(self.info_speed, texts.speed)
        _set(self.info_zoom, texts.zoom)
        if texts.status is not None:
            _set(self.status, texts.status)

    # -- callbacks -----------------------------------------------------------------------------------
    def _on_sensors(self, change: dict[str, Any]) -> None:
        value = change.get("new")
        show = value if isinstance(value, bool) else str(value).strip().lower() in ("1", "true", "yes", "on")
        self.sensors.icon = "check" if show else ""
        self.live.show_laser = show
        self.live.request_redraw()

    def _on_live_error(self, err: BaseException) -> None:
        self._warn(f"The live view hit a problem: {err}")

    def _safe(self, action: str, fn: Any) -> Any:
        """Widget callback wrapper: failures become a warning in the page and a notification."""

        def wrapper(*args: Any) -> None:
            try:
                fn(*args)
            except Exception as err:
                if not isinstance(err, PmkError | ValueError):
                    log.exception("%s failed", action)
                self._warn(f"{action} failed: {err}")
                with contextlib.suppress(Exception):
                    self.ctx.notify(f"{action} failed: {err}", "error")

        return wrapper

    def _warn(self, message: str) -> None:
        _set(self.warning, _note(message) if message else "")

    def _set_running(self, running: bool) -> None:
        self.preview_button.layout.display = "none" if running else ""
        self.disconnect_button.layout.display = "" if running else "none"
        self.sensors.layout.display = "" if running else "none"
        self.zoom_bar.layout.display = "" if running else "none"
        self.live.canvas.layout.display = "" if running else "none"
        if not running and self.ctx.current_map is None:
            self.preview_button.layout.display = "none"
