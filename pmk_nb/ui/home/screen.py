"""Home screen: the current map, Preview / Stop preview, Show sensors, zoom, and the live info panel.

As in the original app (thesis 3.2.5, 4.2.1.1, 5.2.3.1, 5.2.3.4): the current map is the last one
sent to the chair; when it cannot be shown there is a warning and no Preview button; Preview
connects to the chair and starts the live view, Stop preview stops it (only the preview: the
button is neither red nor called Disconnect, as it is no emergency stop); "Show sensors" toggles the
laser rays; the zoom buttons sit at the map's upper-right corner; position, heading, speed and zoom
are shown in the information panel and updated live, with a clear "no data" state when odometry
stops.  Like the original's wifi dialog, showing Home checks that the chair answers and warns if not.

A missing ``NAME-visualization.png`` preview image gets a warning but keeps Preview: the image is
only a thumbnail here, and refusing to show the map the chair really uses because its thumbnail is
gone would block the user for nothing.  A missing or unreadable map file hides Preview.

With ``autostart`` (``pmk demo``, kiosks: see :data:`pmk_nb.ui.common.context.AUTOSTART_ENV`) the preview
starts by itself whenever Home is shown, unless the user pressed Stop preview.

Where things live: the widgets in :mod:`pmk_nb.ui.home.layout`, the texts in
:mod:`pmk_nb.ui.home.info`, the link's lifecycle in :mod:`pmk_nb.ui.home.preview`, the map
grid in :mod:`pmk_nb.ui.home.map_grid`, the up-front checks in :mod:`pmk_nb.ui.home.checks`, the canvas
in :mod:`pmk_nb.ui.live.view`.  This module wires them to the user's actions.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.errors import PmkError
from pmk_nb.speech import phrases
from pmk_nb.ui.common.widgets import error_text, escape
from pmk_nb.ui.drive.panel import DrivePanel
from pmk_nb.ui.fleet.panel import FleetPanel
from pmk_nb.ui.goals.heading_buttons import HeadingButtons
from pmk_nb.ui.goals.panel import GoalPanel
from pmk_nb.ui.home.checks import ChairProbe, preview_image_problem
from pmk_nb.ui.home.fit import FitChannel
from pmk_nb.ui.home.info import (
    NO_PROFILE_TEXT,
    PRESS_PREVIEW_TEXT,
    chair_silent_text,
    connection_state,
    hint_html,
    info_texts,
    warning_html,
)
from pmk_nb.ui.home.layout import HomeLayout
from pmk_nb.ui.home.live_region import Announcer
from pmk_nb.ui.home.map_grid import MapGridCache
from pmk_nb.ui.home.own_map import CHAIRS_MAP, ChairMap, OwnMap, map_label_html
from pmk_nb.ui.home.preview import PreviewController
from pmk_nb.ui.home.statusline import status_line
from pmk_nb.ui.home.stop_latch import StopLatch
from pmk_nb.ui.live.nav_layers import NavLayers
from pmk_nb.ui.live.path_layer import LivePathLayer
from pmk_nb.ui.live.render_loop import RenderLoop
from pmk_nb.ui.live.tools import MapTools
from pmk_nb.ui.live.view import PAGE_CANVAS_FPS as LIVE_FPS
from pmk_nb.ui.live.view import LiveView
from pmk_nb.ui.plots.panel import PlotsPanel
from pmk_nb.ui.record.panel import RecordPanel
from pmk_nb.ui.rooms.guide import RoomsGuide
from pmk_nb.ui.rooms.picker import RoomPicker
from pmk_nb.ui.rooms.picks import RoomPicks

if TYPE_CHECKING:
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.ui.common.context import AppContext, CurrentMap

log = logging.getLogger(__name__)

INFO_HZ = 4.0  # info panel refresh rate: text widgets need no 20 fps
#: Seconds between updates of the Details card's readings (position, speed, zoom, laser) while the
#: card is closed (the state and the status line keep INFO_HZ): a turning chair's heading changed the
#: hidden position text 4 times a second, a widget message each for the kernel, Voilà and the page,
#: as many as half its frames on a classroom page.  Opening the card or a zoom updates them at once.
HIDDEN_TEXTS_S = 1.0
#: The live canvas until the page has said how much room the map has (pmk_nb/ui/home/fit.py):
#: then it takes that room, whatever the map's shape, up to LiveView.PAGE_MAX.
CANVAS_MAX = (920, 560)
DEFAULT_FOOTPRINT = 0.35  # m, when the profile has no usable chair radius


class HomeScreen:
    """The Home screen; ``widget`` is its content, ``info_widget`` its part of the info panel.

    Args:
        ctx: the session (current map, chair profile, link, notifications).
        canvas_width, canvas_height: largest live view size in pixels (it takes the map's shape).
        fps: frame-rate cap of the live view (None: the session's ``live_fps``, else the live view's own).
        autostart: start the preview whenever Home is shown (:meth:`on_show`), unless the user
            pressed Stop preview; for demos and kiosks.
    """

    def __init__(
        self,
        ctx: AppContext,
        *,
        canvas_width: int = CANVAS_MAX[0],
        canvas_height: int = CANVAS_MAX[1],
        fps: float | None = None,
        autostart: bool = False,
    ) -> None:
        self.ctx = ctx
        self.autostart = bool(autostart)
        self._user_stopped = False
        self._map_ok = False
        self.maps = MapGridCache()
        self.own = OwnMap()  # the chair's own /map while the preview runs (pmk_nb/ui/home/own_map.py)
        fps = fps if fps is not None else ctx.live_fps if ctx.live_fps is not None else LIVE_FPS
        self.live = LiveView(canvas_width, canvas_height, fps=fps, fit_to_map=True, page_chair=True)  # issue 41
        self.live.on_zoom_change(lambda _z: self.refresh_info(texts=True))
        self.live.on_error(self._on_live_error)
        self.ui = HomeLayout(self.live.canvas, self.live.toolbar.widget)
        self._texts_at = -math.inf  # when the Details card's readings were last written
        self._texts_state = ""  # the connection state they were written in
        self.ui.details_toggle.observe(self._on_details, names="value")
        self.widget = self.ui.widget
        # the text panel is Home's Details card over the map (pmk_nb/ui/home/layout.py); the
        # navigation's panel keeps only the messages on Home
        self.info_widget = w.VBox([])
        self.info_widget.add_class("pmk-home-info-slot")
        # the page's room for the map and the panels over it (pmk_nb/ui/home/fit.py)
        self.fit = FitChannel(self.live)
        # rooms by name and spoken feedback (pmk_nb/ui/rooms/guide.py): "You are in" in the info
        # panel, the Go to… box and the (hidden) speech widgets under the map
        self.rooms = RoomsGuide(self.live, on_error=lambda m: self.ctx.notify(m, "error", inline=True))
        self.ui.info.widget.children = (*self.ui.info.widget.children, self.rooms.panel.here)
        self.ui.widget.children = (*self.ui.widget.children, self.rooms.panel.widget, self.rooms.speech.widget)
        # the same news for screen readers: aria-live regions (pmk_nb/ui/home/live_region.py)
        self.announcer = Announcer()
        self.rooms.speech.listeners.append(self.announcer.phrase)
        self.ui.widget.children = (*self.ui.widget.children, self.announcer.widget)
        # tap-to-go (pmk_nb/ui/goals/panel.py): Set destination, the goal's status, Cancel; under the map
        self.goal = GoalPanel(self.live, on_error=lambda m: self.ctx.notify(m, "error", inline=True))
        self.goal.speak = self.rooms.speech.say  # "Going to the destination.", "Arrived at …"
        # the joystick, Stop and Slow (pmk_nb/ui/drive/panel.py): over the map while Drive is on
        self.drive = DrivePanel(claims_dir=ctx.config_dir / "drive", kiosk=ctx.kiosk)  # shared by every page's kernel
        self.drive.on_stop = self.rooms.say_stopped  # "Stopped." spoken (pmk_nb/ui/rooms/guide.py)
        self.ui.map_stack.children = (*self.ui.map_stack.children, self.drive.widget)
        # a press of Stop is said even when the chair was not moving (the drive reports only stops)
        self.drive.stop_button.on_click(lambda _b: self.announcer.phrase(phrases.stopped("stop button")))
        # another page's Stop cancels this page's goals and refuses new ones (issue 38, stop_latch.py)
        self.stop_latch = StopLatch(ctx.config_dir / "drive", self.drive.member)
        self._floating_tools()
        self.ui.preview_box.children = (*self.ui.preview_box.children, self.goal.widget, self.fit.widget)
        # issue 29: the Plots toggle in the floating bar; its panel, the map tools and Record under the map
        self.plots = PlotsPanel()  # pmk_nb/ui/plots/panel.py: speed and turn rate, the topic inspector
        self.ui.add_tool(self.plots.toggle)
        # scale bar, grid, coordinates, Measure, Set pose (pmk_nb/ui/live/tools.py)
        self.tools = MapTools(self.live, ctx)
        # Record, Stop recording, downloads (pmk_nb/ui/record/panel.py)
        self.recorder = RecordPanel(ctx)
        self.ui.preview_box.children = (
            *self.ui.preview_box.children,
            self.plots.widget,
            self.tools.widget,
            self.recorder.widget,
        )
        self._map_layers()
        self.fleet = FleetPanel(ctx, self)  # issue 26: several chairs, one in control (pmk_nb/ui/fleet/panel.py)
        self.preview = PreviewController(on_state=self.refresh_info, on_unreachable=self._on_unreachable)
        self.probe = ChairProbe(self._on_probe)
        ui = self.ui
        ui.preview_button.on_click(self._safe("Starting the preview", lambda _b: self._user_start()))
        ui.disconnect_button.on_click(self._safe("Stopping the preview", lambda _b: self._user_stop()))
        ui.zoom_in_button.on_click(self._safe("Zooming in", lambda _b: self.live.zoom_in()))
        ui.zoom_out_button.on_click(self._safe("Zooming out", lambda _b: self.live.zoom_out()))
        ui.sensors.observe(self._safe("Toggling sensors", self._on_sensors), names="value")
        self._info_loop = RenderLoop(self.refresh_info, INFO_HZ, on_error=self._on_live_error)
        self._unsub_map = ctx.observe_current_map(self._on_current_map)
        self._show_running(False)
        self.refresh_map()

    def _map_layers(self) -> None:
        """What the navigation stack shows on the live map: its plan, and (issue 40) the costmaps,
        footprint, local plan and markers, a toggle each under the map."""
        self.path = LivePathLayer()  # pmk_nb/ui/live/path_layer.py: Nav2's /plan, move_base's plan
        self.live.overlays.append(self.path)
        self.layers = NavLayers(self.live)  # pmk_nb/ui/live/nav_layers.py
        self.ui.preview_box.children = (*self.ui.preview_box.children, self.layers.widget)
        if self.live.page_widget is not None:  # the page draws the chair (issue 41: ui/live/page_script.py)
            self.ui.preview_box.children = (*self.ui.preview_box.children, self.live.page_widget)

    def _floating_tools(self) -> None:
        """The map's floating bar (issue 28): Drive, Go to (two taps to a room), Set destination
        (its heading card over the map: compass buttons, no drag needed)."""
        ui = self.ui
        ui.add_tool(self.drive.toggle)
        # Go to a room in two taps (pmk_nb/ui/rooms/picker.py): favourites and recent rooms first
        picks = RoomPicks(self.ctx.config_dir)
        self.goto = RoomPicker(self.rooms, picks, lambda: getattr(self.ctx.current_map, "name", None))
        ui.add_tool(self.goto.button)
        # Set destination in the bar (the map is the screen: under it is out of sight), and while it
        # is on, a card with the heading buttons (pmk_nb/ui/goals/heading_buttons.py)
        goal = self.goal
        goal.widget.children[0].children = tuple(c for c in goal.widget.children[0].children if c is not goal.toggle)
        ui.add_tool(goal.toggle)
        self.heading = HeadingButtons(lambda h: setattr(goal.picker, "heading", h))
        hint = w.HTML("Tap the map where the chair should go.")
        self.goal_card = w.VBox([hint, self.heading.widget], layout=w.Layout(display="none"))
        self.goal_card.add_class("pmk-home-goal-card")
        goal.toggle.observe(self._on_goal_toggle, names="value")
        ui.map_stack.children = (*ui.map_stack.children, self.goto.card, self.goal_card)

    def _on_goal_toggle(self, change: dict[str, Any]) -> None:
        on = change.get("new") is True
        self.goal_card.layout.display = "flex" if on else "none"
        if not on:
            self.heading.reset()  # the next destination faces away from the chair unless chosen again

    # -- public API ----------------------------------------------------------------------------------
    @property
    def running(self) -> bool:
        return self.live.running

    @property
    def preview_button(self) -> w.Button:
        return self.ui.preview_button

    @property
    def disconnect_button(self) -> w.Button:
        return self.ui.disconnect_button

    def on_show(self) -> None:
        """Called by the app when Home becomes visible: re-check the map files and the chair.

        With ``autostart`` this starts the preview (which reports an unreachable chair itself);
        otherwise a background probe warns early when the chair does not answer.
        """
        self.refresh_map()
        if self.running:
            return
        if self.autostart and not self._user_stopped and self._map_ok and self.ctx.profile() is not None:
            self.start_preview()
            return
        self.check_chair()

    def check_chair(self) -> threading.Thread | None:
        """Probe the chair's rosbridge port in a thread; ``chair_note`` warns when it does not answer."""
        profile = self.ctx.profile()
        if profile is None:
            self.probe.cancel()
            self.ui.chair_note.value = warning_html(NO_PROFILE_TEXT)
            return None
        return self.probe.check(profile.host, int(profile.port))

    def start_preview(self) -> bool:
        """Load the current map, connect the chair link and start drawing; False (with a warning) if not."""
        if self.running:
            return True
        grid = self.refresh_map()
        if grid is None and not self._map_ok:
            return False
        try:
            link = self.ctx.link()
        except PmkError as err:
            self._warn(str(err))
            return False
        profile = self.ctx.profile()
        footprint = float(profile.footprint_radius or DEFAULT_FOOTPRINT) if profile is not None else DEFAULT_FOOTPRINT
        self.live.footprint_radius = footprint if math.isfinite(footprint) and footprint > 0 else DEFAULT_FOOTPRINT
        self.live.show_laser = bool(self.ui.sensors.value)
        if grid is not None:
            self.live.set_map(grid)
        self.probe.cancel()  # the preview's own connection reports on the chair from now on
        self._warn("")
        self.ui.chair_note.value = ""
        if self.ctx.current_map is None:
            self.ui.map_note.value = ""  # the hint to press Preview
        self._show_running(True)
        self.live.start(link)
        self.goal.attach(link)
        self.tools.attach(link)
        self.plots.attach(link)
        self.path.attach(link, profile.plan_topic if profile is not None else "auto")
        self.layers.attach(link)
        self.drive.offer(link, profile)
        self.stop_latch.attach(link, profile.cmd_vel_topic if profile is not None else None)
        # routes use the accessibility check's chair width (Settings), else the footprint's diameter
        self.rooms.attach(link, getattr(profile, "chair_width", None) or 2 * self.live.footprint_radius)
        if profile is not None:
            self.rooms.configure_speech(profile.speech_on, profile.speech_voice, profile.speech_rate)
        self._info_loop.start()
        # the canvas shows the map meanwhile and the chair once data flows
        self.preview.start(link)
        self.own.attach(link)  # whatever the chair publishes on /map is shown once it arrives
        self.refresh_info()
        return True

    def stop_preview(self) -> None:
        """Stop drawing and the chair's streams (the link itself stays open for other screens)."""
        self.live.stop()
        self._info_loop.stop()
        self.preview.stop()
        self.own.attach(None)  # stopped: Home shows the map sent from here again (if any)
        self.live.attach(None)
        self.goal.attach(None)
        self.tools.attach(None)
        self.plots.attach(None)
        self.path.attach(None)
        self.layers.attach(None)
        self.drive.offer(None, None)
        self.stop_latch.attach(None)
        self.rooms.attach(None)
        self._show_running(False)
        self.refresh_info()

    def close(self) -> None:
        self.fleet.close()
        self.stop_preview()
        self.recorder.close()
        self._unsub_map()
        self.plots.close()
        self.layers.close()
        self.live.close()

    # -- map -----------------------------------------------------------------------------------------
    def refresh_map(self) -> OccupancyGrid | None:
        """Show the current map's name; load its grid (cached) or warn and hide Preview."""
        ui, current = self.ui, self.ctx.current_map
        if current is None and self.ctx.profile() is not None:
            return self._chair_map_only()
        if current is None:
            ui.map_note.value = ""
            ui.map_label.value = "<b>No map yet.</b> Convert a map and send it to the chair on the Maps screen."
            ui.info.map.value = "Map: <i>none</i>"
            self._map_problem("No current map: send a map to the chair from the Maps screen first.")
            self.rooms.set_map(None)
            self.goto.button.layout.display = "none"
            return None
        ui.map_label.value = f"Current map: <b>{escape(current.name)}</b>"
        ui.info.map.value = f"Map: <b>{escape(current.name)}</b>"
        try:
            grid = self.maps.load(current)
        except (PmkError, OSError, ValueError) as err:
            ui.map_note.value = ""
            self._map_problem(f"The map '{current.name}' cannot be shown: {err}. Convert and send it again.")
            return None
        ui.map_note.value = warning_html(preview_image_problem(current) or "")
        self.own.set_local(current.name, grid, current.yaml)
        shown = self.own.current
        if shown is not None and not shown.is_sent_map:  # the chair uses another map: that is shown
            self._show_chair_map(shown)
            return shown.grid
        self.live.set_map(grid)  # shown connected or not (the same grid again is a no-op)
        self.rooms.set_map(current.yaml)
        self.goto.button.layout.display = "" if self.rooms.rooms is not None else "none"
        self._map_ok = True
        self._show_running(self.running)
        if not self.running:
            self._warn("")
        return grid

    def _chair_map_only(self) -> OccupancyGrid | None:
        """No map sent from this dashboard, but a chair: Preview shows the chair's own map."""
        self.ui.map_note.value = "" if self.running else hint_html(PRESS_PREVIEW_TEXT)
        self.own.set_local(None, None)
        shown = self.own.current
        if shown is not None:
            self._show_chair_map(shown)
            return shown.grid
        self.ui.map_label.value = map_label_html(CHAIRS_MAP, False)
        self.ui.info.map.value = f"Map: <i>{escape(CHAIRS_MAP)}</i>"
        self.rooms.set_map(None)
        self._map_ok = True
        self._show_running(self.running)
        if not self.running:
            self._warn("")
        return None

    def _show_chair_map(self, chair_map: ChairMap) -> None:
        """Show the map the chair publishes (the sent map's grid, already loaded, when it is that map)."""
        current, local = self.ctx.current_map, self.maps.grid
        if current is None:
            self.ui.map_note.value = ""  # the chair's map is shown: no need to press Preview for it
        sent = chair_map.is_sent_map and current is not None and local is not None
        self.live.set_map(local if sent and local is not None else chair_map.grid)
        self.rooms.set_map(current.yaml if sent and current is not None else None)
        self.ui.map_label.value = map_label_html(chair_map.name, sent)
        self.ui.info.map.value = f"Map: <b>{escape(chair_map.name)}</b>"
        self._map_ok = True
        self._show_running(self.running)

    def _map_problem(self, message: str) -> None:
        self._map_ok = False
        self._show_running(self.running)
        self._warn(message)

    def _on_current_map(self, _current: CurrentMap | None) -> None:
        self.goal.forget_finished()  # a destination on the old map is not this map's
        grid = self.refresh_map()
        if self.running and grid is not None:
            self.live.set_map(grid)

    # -- info panel ----------------------------------------------------------------------------------
    def connection_state(self) -> tuple[str, float | None]:
        """("off"|"connecting"|"live"|"stale"|"unreachable", seconds since the last odometry or None)."""
        return connection_state(self.preview.snapshot())

    def _on_details(self, change: dict[str, Any]) -> None:
        if change.get("new") is True:
            self.refresh_info(texts=True)

    def refresh_info(self, texts: bool = False) -> None:
        """Update position, speed, zoom and state texts (a widget whose text is unchanged sends nothing).

        ``texts``: write the Details card's readings now, even while it is closed (see HIDDEN_TEXTS_S).
        A change of connection state writes them at once too: a silent chair's speed is not current.
        """
        snap = self.preview.snapshot()
        state, age = connection_state(snap)
        live = self.live
        reading = info_texts(state, age, snap.pose, snap.odom, live.zoom, live.zoom_factor, snap.scan, live.grid)
        self.live.stale = state == "stale"  # the loop redraws: the chair turns grey
        info = self.ui.info
        info.state.value = reading.state
        now = time.monotonic()
        due = now - self._texts_at >= HIDDEN_TEXTS_S or state != self._texts_state
        if texts or self.ui.details_toggle.value or due:
            self._texts_at, self._texts_state = now, state
            info.pos.value = reading.position
            info.speed.value = reading.speed
            info.zoom.value = reading.zoom
            info.laser.value = reading.laser
        self.drive.refresh()
        stopped = self.stop_latch.latched  # any page's Stop: no Set destination, no Go to (issue 38)
        self.goal.set_stopped(stopped)
        self.goto.set_stopped(stopped)
        self.fit.tick()
        here = self.rooms.panel.here_name
        doing = self.drive.doing() or self.goal.doing() or self._room_doing()
        self.ui.statusline.value = status_line(state, age, here, snap.odom, doing)
        if reading.status is not None:
            self.ui.status.value = reading.status
        chair_map = self.own.take()
        if chair_map is not None:
            self._show_chair_map(chair_map)
        self.rooms.tick(snap.pose or snap.odom, state)
        self.plots.tick(snap.odom if state == "live" else None)
        self.path.tick(snap.pose or snap.odom)
        self.layers.tick()
        self.goal.tick(snap.pose or snap.odom, self.rooms.going_to)  # not "No destination" during a Go to
        self.announcer.tick(state, alerts=reading.alerts)  # the same reading the panel shows

    def _room_doing(self) -> str | None:
        """The status line's last words while a Go to goal runs ("Going to Kitchen"), else None."""
        handle, route = self.rooms.handle, self.rooms.route
        if handle is None or route is None or handle.progress().done:
            return None
        return f"Going to {route.destination.label}"

    # -- callbacks -----------------------------------------------------------------------------------
    def _user_start(self) -> None:
        self._user_stopped = False
        self.start_preview()

    def _user_stop(self) -> None:
        self._user_stopped = True  # autostart respects the choice until Preview is pressed again
        self.stop_preview()

    def _on_probe(self, host: str, port: int, problem: str | None) -> None:
        self.ui.chair_note.value = warning_html(chair_silent_text(host, port, problem) if problem else "")

    def _on_unreachable(self, message: str) -> None:
        # no chair, no preview (as the original app): stop, and say why and what to do
        self.stop_preview()
        self._warn(message + " Check the Settings screen and the network, then press Preview again.")
        self.ctx.notify(message, "warning", inline=True)  # shown above the map: once

    def _on_sensors(self, change: dict[str, Any]) -> None:
        value = change.get("new")
        show = value if isinstance(value, bool) else str(value).strip().lower() in ("1", "true", "yes", "on")
        self.ui.sensors.icon = "eye" if show else "eye-slash"  # its own icon: the only label on a phone
        self.live.show_laser = show
        self.live.request_redraw()

    def _on_live_error(self, err: BaseException) -> None:
        self._warn(f"The live view hit a problem: {err}")

    def _safe(self, action: str, fn: Callable[..., object]) -> Callable[..., None]:
        """Widget callback wrapper: failures become a warning in the page and a notification."""

        def wrapper(*args: Any) -> None:
            try:
                fn(*args)
            except Exception as err:
                if not isinstance(err, PmkError | ValueError):
                    log.exception("%s failed", action)
                message = error_text(err, action)
                self._warn(message)
                self.ctx.notify(message, "error", inline=True)

        return wrapper

    def _warn(self, message: str) -> None:
        self.ui.warning.value = warning_html(message)

    def _show_running(self, running: bool) -> None:
        self.ui.show_running(running, can_preview=self._map_ok)
        self.tools.refresh_scale()
