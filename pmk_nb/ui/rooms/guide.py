"""Home's rooms by name: "You are in", the "Go to…" list, the route on the map, Go / Cancel, and speech.

Wiring only: the rooms, routes and goals come from :mod:`pmk_nb.guide` (``go_to``: the same call
a notebook makes), the goal's progress from the link's goal handle, the words from
:mod:`pmk_nb.speech.phrases`. :meth:`RoomsGuide.tick` runs on Home's info timer (4 Hz): it
updates "You are in", reads the goal's latest progress (the handle stores it on the link's
thread), says what changed, and hands the next phrase to the page.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pmk_nb.access import sidecar_path
from pmk_nb.chair.link import GoalsStopped
from pmk_nb.defaults import DEFAULT_CHAIR_WIDTH
from pmk_nb.errors import PmkError
from pmk_nb.guide import NoAccessibleRoute, NoGraph, RoomsMap, go_to, load_rooms
from pmk_nb.speech import phrases
from pmk_nb.ui.common.speech_output import SpeechOutput
from pmk_nb.ui.common.widgets import error_text
from pmk_nb.ui.rooms.layer import RoomsOverlay
from pmk_nb.ui.rooms.panel import RoomsPanel

if TYPE_CHECKING:
    from pmk_nb.guide import Navigator, Route
    from pmk_nb.ui.live.view import LiveView

log = logging.getLogger(__name__)
LOST_STATES = ("stale", "unreachable", "connecting")
NO_ROOMS = "This map has no rooms file: convert the building again on the Maps screen to go to rooms by name."


class RoomsGuide:
    """The rooms panel's behaviour; ``panel`` holds its widgets, ``speech`` the spoken feedback."""

    def __init__(self, live: LiveView, *, on_error: Callable[[str], None] | None = None) -> None:
        self.live = live
        self.panel = RoomsPanel()
        self.speech = SpeechOutput()
        self.overlay = RoomsOverlay()
        live.overlays.append(self.overlay)
        self.rooms: RoomsMap | None = None
        self.link: Navigator | None = None
        self.chair_width = DEFAULT_CHAIR_WIDTH  # until the profile says (attach)
        self.route: Route | None = None
        self.handle: Any = None
        self._status: str | None = None
        self._link_state = "off"
        self._lost = False
        self._on_error = on_error
        self._stamp: tuple[str, float] | None = None
        self.panel.search.observe(lambda _c: self._filter(), names="value")
        self.panel.go_button.on_click(self._safe("Going to the room", lambda _b: self.go()))
        self.panel.cancel_button.on_click(self._safe("Cancelling the goal", lambda _b: self.cancel()))
        self.set_map(None)

    # -- setup ---------------------------------------------------------------------------------------
    def set_map(self, yaml: Path | None) -> RoomsMap | None:
        """Load the rooms beside the map ``yaml`` (None: no map); without them, say how to get them."""
        stamp = _stamp(yaml)
        if stamp == self._stamp and (self.rooms is not None or yaml is None):
            return self.rooms  # the same rooms file as shown (a reconverted map has a new one)
        self._stamp = stamp
        self.rooms = None
        if yaml is not None:
            try:
                self.rooms = load_rooms(yaml)
            except PmkError as err:
                log.info("no rooms for %s: %s", yaml, err)
        rooms = self.rooms
        labels = [] if rooms is None else [r.label for r in rooms.destinations()]
        self.overlay.set_labels([] if rooms is None else [(r.label, *_anchor(r.polygon)) for r in rooms.destinations()])
        self.overlay.clear_route()
        self.panel.set_rooms(labels)
        self.panel.show_available(bool(labels), NO_ROOMS if yaml is not None else "")
        self.panel.show_here(None)
        return rooms

    def attach(self, link: Navigator | None, chair_width: float | None = None) -> None:
        """Use ``link`` for the pose and goals (None: preview stopped)."""
        self.link = link
        if chair_width is not None and chair_width > 0:
            self.chair_width = float(chair_width)

    def configure_speech(self, on: bool, voice: str, rate: float) -> None:
        self.speech.configure(on, voice, rate)

    def say_stopped(self, reason: Any) -> None:
        """The drive's stop callback (any thread): "Stopped." with the reason, for who cannot see it."""
        why = str(getattr(reason, "value", reason))
        if why not in phrases.SILENT_STOPS:
            self.speech.say(phrases.stopped(why))

    # -- actions -------------------------------------------------------------------------------------
    def _filter(self) -> None:
        if self.rooms is not None:
            self.panel.set_rooms([r.label for r in self.rooms.search(str(self.panel.search.value or ""))])

    def go(self, room: str | None = None) -> Route | None:
        """Route to ``room`` (default: the one picked in the list) and send the chair; None if not."""
        name = room or self.panel.list.value
        if self.rooms is None or not name:
            self.panel.say("Pick a room first.", "warning")
            return None
        if self.link is None:
            self.panel.say("Start the preview first: the chair's position is needed for the route.", "warning")
            return None
        self.cancel()
        try:
            route, handle = go_to(self.link, self.rooms, name, self.chair_width)
        except GoalsStopped as err:  # a Stop holds on some page of this chair (issue 38)
            self.overlay.clear_route()
            self.panel.say(error_text(err), "warning")
            return None
        except (NoAccessibleRoute, NoGraph) as err:
            self.overlay.clear_route()
            self.panel.say(str(err), "error")
            narrow = err.narrow if isinstance(err, NoAccessibleRoute) else []
            self.speech.say(phrases.route_blocked(err.room, [n for n, _ in narrow]))
            return None
        self.route, self.handle, self._status = route, handle, None
        self.overlay.set_route(route.points, route.goal[:2])
        self.panel.show_goal(True)
        self.panel.say(f"Going to {route.destination.label} ({route.length:.0f} m).")
        self.speech.say(phrases.destination_set(route.destination.label))
        self.live.request_redraw()
        return route

    def cancel(self) -> None:
        """Cancel the running goal (the chair stops; the handle reports "cancelled")."""
        handle = self.handle
        if handle is not None and not handle.progress().done:
            handle.cancel()

    @property
    def going_to(self) -> str | None:
        """The room a Go to… is driving to now (None: no goal of this panel's is running)."""
        handle, route = self.handle, self.route
        if handle is None or route is None or handle.progress().done:
            return None
        return str(route.destination.label)

    # -- the timer -----------------------------------------------------------------------------------
    def tick(self, pose: Any, link_state: str) -> None:
        """Update "You are in", the goal's status and the link's phrases; say the next phrase."""
        rooms = self.rooms
        here = rooms.room_at(float(pose.x), float(pose.y)) if rooms is not None and pose is not None else None
        self.panel.show_here(here.label if here is not None else None)
        self._goal_news()
        self._link_news(link_state)
        self.speech.pump()

    def _goal_news(self) -> None:
        handle, route = self.handle, self.route
        if handle is None or route is None:
            return
        progress = handle.progress()
        status = progress.status.value
        room = route.destination.label
        left = f", {progress.remaining_m:.1f} m left" if progress.remaining_m is not None else ""
        if not progress.done:
            self.panel.say(f"Going to {room}: {status}{left}.")
        elif status != self._status:
            level = "info" if status == "arrived" else "warning"
            done = f"Arrived at {room}." if status == "arrived" else f"Goal {status}: {progress.message}"
            self.panel.say(done, level)
            self.panel.show_goal(False)
            self.overlay.clear_route()
            self.live.request_redraw()
            if status == "arrived":
                self.speech.say(phrases.arrived(room))
            elif status == "cancelled":
                self.speech.say(phrases.stopped("cancel"))
            else:
                self.speech.say(phrases.goal_failed(room))
        self._status = status

    def _link_news(self, state: str) -> None:
        before, self._link_state = self._link_state, state
        if state == before:
            return
        if state in LOST_STATES and before == "live":
            self._lost = True
            self.speech.say(phrases.connection_lost())
        elif state == "live" and self._lost:
            self._lost = False
            self.speech.say(phrases.connection_regained())
        elif state == "off":
            self._lost = False

    def _safe(self, action: str, fn: Callable[[Any], object]) -> Callable[[Any], None]:
        def run(arg: Any) -> None:
            try:
                fn(arg)
            except Exception as err:
                if not isinstance(err, PmkError):
                    log.exception("%s failed", action)
                message = error_text(err, action)
                self.panel.say(message, "error")
                if self._on_error is not None:
                    self._on_error(message)

        return run


def _stamp(yaml: Path | None) -> tuple[str, float] | None:
    """(path, modification time) of the map's rooms file: tells a reconverted map apart."""
    if yaml is None:
        return None
    rooms = sidecar_path(yaml)
    try:
        return str(rooms), rooms.stat().st_mtime
    except OSError:
        return str(rooms), 0.0


def _anchor(polygon: Any) -> tuple[float, float, float, float]:
    """Where a room's name goes (a point inside it) and the room's width and height in metres."""
    inside = polygon.centroid if polygon.contains(polygon.centroid) else polygon.representative_point()
    x0, y0, x1, y1 = polygon.bounds
    return float(inside.x), float(inside.y), x1 - x0, y1 - y0
