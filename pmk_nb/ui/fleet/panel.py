"""Home's Fleet panel (issue 26): several chairs live on one page, one of them in control.

A "Fleet" toggle in Home's floating bar opens a card over the map: add a saved chair (or all of
them; an instructor: the class's simulated chairs), and a row per chair with its colour,
connection, map, pose and goal, and a Control button.  The page's own chair joins first and is in
control; Control on another row re-points Home's live view, Drive, Set destination and Go to at
that chair's link, which is already open (:class:`~pmk_nb.chair.fleet_links.FleetLinks`): no
reconnect, the switch takes a fraction of a second (``switch_s``).  The map shows every chair on
it in its colour (:mod:`pmk_nb.ui.fleet.layer`).  A chair that does not answer says so in its
row; the others go on.

Every action checks what the page sent (a name must be a saved chair, a row's chair in the fleet)
and is behind the kiosk PIN (:func:`~pmk_nb.ui.common.context.needs_pin`): a locked kiosk's rider cannot
take another chair, or give theirs away.
"""

from __future__ import annotations

import logging
import time
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.chair import (
    ChairStatus,
    Fleet,
    FleetError,
    FleetLinks,
    FleetMember,
    NoChairChosen,
    NotInFleet,
    SameAddress,
    row_words,
)
from pmk_nb.errors import SettingsError
from pmk_nb.ui.common.context import needs_pin
from pmk_nb.ui.common.style import TOUCH_PX
from pmk_nb.ui.common.widgets import button, error_text, escape
from pmk_nb.ui.fleet.goals import ParkedGoals, park, resume
from pmk_nb.ui.fleet.layer import FleetLayer, Marker
from pmk_nb.ui.live.render_loop import RenderLoop

if TYPE_CHECKING:
    from pmk_nb.ui.common.context import AppContext
    from pmk_nb.ui.fleet.home_role import FleetHome

log = logging.getLogger(__name__)

ROWS_HZ = 4.0  # rows and markers: text needs no more, a watched chair's odometry comes at 5 Hz
FLEET_CSS = """<style>
.pmk-app .pmk-home-toolbar > .pmk-fleet-card { position: static; flex: 1 1 100%; box-sizing: border-box;
   max-width: 560px; max-height: 60vh; overflow: auto; gap: 6px;
   background: rgba(255, 255, 255, 0.97); border-radius: 12px; padding: 8px 12px;
   box-shadow: 0 2px 10px rgba(0, 0, 0, .3); }
.pmk-app .pmk-fleet-row { gap: 8px; align-items: center; border-top: 1px solid #ddd; padding-top: 4px; }
.pmk-app .pmk-fleet-row .pmk-fleet-text { flex: 1 1 auto; min-width: 0; }
.pmk-app .pmk-fleet-swatch { display: inline-block; width: 1.1em; height: 1.1em; border-radius: 50%;
   vertical-align: middle; margin-right: 6px; border: 2px solid #fff; box-shadow: 0 0 0 1px #555; }
.pmk-app .pmk-fleet-row.pmk-fleet-in-control { background: #eef6ff; }
.pmk-app .pmk-fleet-head { justify-content: space-between; align-items: center; }
</style>"""
#: The card is the last item of Home's floating bar, on a row of its own: it opens below the bar's buttons
#: however many rows they wrap to, never over its own Fleet button (issue 40: at 1280x800 the bar took two
#: rows and the card, placed over the map's corner, covered it; it had no close button either).


class _Row:
    """One chair's row: its words and its Control / Remove buttons."""

    def __init__(self, member: FleetMember) -> None:
        self.name = member.name
        self.text = w.HTML("")
        self.text.add_class("pmk-fleet-text")
        self.control = button("Control", "pmk-fleet-control", icon="gamepad", tooltip=f"Drive and guide {member.name}")
        self.remove = button("", "pmk-fleet-remove", icon="times", tooltip=f"Stop watching {member.name}")
        self.widget = w.HBox([self.text, self.control, self.remove])
        self.widget.add_class("pmk-fleet-row")
        self._shown: ChairStatus | None = None

    def show(self, status: ChairStatus) -> None:
        if status == self._shown:
            return
        self._shown = status
        words = row_words(status)
        self.text.value = (
            f"<span class='pmk-fleet-swatch' style='background:{escape(status.colour)}'></span>"
            f"<b class='pmk-fleet-name'>{escape(status.name)}</b>"
            f"{' <i>(in control)</i>' if status.controlled else ''}<br>"
            f"<span class='pmk-fleet-connection' data-state='{escape(status.connection)}'>"
            f"{escape(words['connection'])}</span> · <span class='pmk-fleet-map'>{escape(words['map'])}</span><br>"
            f"<span class='pmk-fleet-pose'>{escape(words['pose'])}</span> · "
            f"<span class='pmk-fleet-goal'>{escape(words['goal'])}</span>"
        )
        self.control.disabled = status.controlled
        self.remove.disabled = status.controlled
        if status.controlled:
            self.widget.add_class("pmk-fleet-in-control")
        else:
            self.widget.remove_class("pmk-fleet-in-control")


class FleetPanel:
    """The Fleet toggle (in Home's bar), its card over the map and the map's fleet markers.

    Args:
        ctx: the page's session (profiles, kiosk lock); ``ctx.fleet`` is set while a fleet is open.
        home: the Home screen whose live view, Drive, Set destination and Go to follow the chair in control
            (what the panel uses of it: :class:`~pmk_nb.ui.fleet.home_role.FleetHome`).
    """

    def __init__(self, ctx: AppContext, home: FleetHome, *, links: FleetLinks | None = None) -> None:
        self.ctx, self.home = ctx, home
        self.model = Fleet()
        self.links = links or FleetLinks()
        self.layer = FleetLayer()
        home.live.overlays.append(self.layer)
        self.rows: dict[str, _Row] = {}
        self._goals: dict[str, ParkedGoals] = {}  # a chair's goals from this page, parked when control moved
        self.switch_s: float | None = None  # how long the last change of control took (measured)
        self.toggle = w.ToggleButton(value=False, description="Fleet", icon="users")
        self.toggle.tooltip = "Several chairs: watch them all, drive one"
        self.toggle.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="110px")
        self.toggle.add_class("pmk-fleet-toggle")
        self.choice = w.Dropdown(options=[], description="Chair", layout=w.Layout(width="auto"))
        self.choice.add_class("pmk-fleet-choice")
        self.add_button = button("Add", "pmk-fleet-add", icon="plus")
        self.add_all_button = button("Add all saved chairs", "pmk-fleet-add-all", icon="users")
        self.class_button = button("Open the class's fleet", "pmk-fleet-class", icon="graduation-cap")
        self.note = w.HTML("")
        self.note.add_class("pmk-fleet-note")
        self.rows_box = w.VBox([])
        self.rows_box.add_class("pmk-fleet-rows")
        tools = w.HBox([self.choice, self.add_button, self.add_all_button, self.class_button])
        tools.layout.flex_flow = "row wrap"
        self.close_button = button("Close", "pmk-fleet-close", icon="times", tooltip="Close the Fleet card")
        self.close_button.on_click(lambda _b: setattr(self.toggle, "value", False))
        head = w.HBox([w.HTML("<b>Fleet</b>"), self.close_button])
        head.add_class("pmk-fleet-head")
        self.card = w.VBox([w.HTML(FLEET_CSS), head, tools, self.rows_box, self.note])
        self.card.add_class("pmk-fleet-card")
        self.card.layout.display = "none"
        self.toggle.observe(self._on_toggle, names="value")
        self.add_button.on_click(self._act("Adding a chair", lambda _b: self.add(self.choice.value)))
        self.add_all_button.on_click(self._act("Adding the saved chairs", lambda _b: self.add_all()))
        self.class_button.on_click(self._act("Opening the class's fleet", lambda _b: self.open_class()))
        self._loop = RenderLoop(self.tick, ROWS_HZ, on_error=lambda err: self._say(error_text(err), "error"))
        home.ui.add_tool(self.toggle)
        home.ui.toolbar.children = (*home.ui.toolbar.children, self.card)

    # -- sources -------------------------------------------------------------------------------------
    def _on_toggle(self, change: dict[str, Any]) -> None:
        on = change.get("new") is True  # a page may send anything: only a real True opens
        self.card.layout.display = "flex" if on else "none"
        if on:
            self._refresh_choices()

    def _refresh_choices(self) -> None:
        try:
            names = self.ctx.profiles.names()
        except Exception as err:  # an unreadable profile file: the row of tools says so
            self._say(error_text(err, "Reading the saved chairs"), "error")
            names = []
        taken = {m.name for m in self.model.members}
        self.choice.options = [n for n in names if n not in taken]
        more = "" if self.choice.options else "none"  # every saved chair is in: nothing to pick
        self.choice.layout.display = self.add_button.layout.display = self.add_all_button.layout.display = more
        self.class_button.layout.display = "" if _class_settings() is not None else "none"

    @needs_pin("Fleet")
    def add(self, name: object) -> FleetMember:
        """Add the saved chair ``name`` (checked: a page can send any value).

        Raises:
            NoChairChosen: none picked (the list's blank choice); SettingsError: no saved chair of that name;
            SameAddress: another chair of the fleet has its address.
        """
        if name is None or name == "":
            raise NoChairChosen()
        if not isinstance(name, str) or name not in self.ctx.profiles.names():
            raise SettingsError(f"There is no saved chair called {str(name)[:80]!r}.")
        member = self._join(self.ctx.profiles.get(name), "profile")
        self._refresh_choices()
        return member

    @needs_pin("Fleet")
    def add_all(self) -> list[FleetMember]:
        """Add every saved chair (up to the fleet's cap); a chair at an address already in is named, not added."""
        members, skipped = [], []
        for profile in self.ctx.profiles.list():
            try:
                members.append(self._join(profile, "profile"))
            except SameAddress as err:
                skipped.append(err)
        self._refresh_choices()
        if skipped:
            self._say(" ".join(err.message for err in skipped), "error")
        return members

    @needs_pin("Fleet")
    def open_class(self) -> list[FleetMember]:
        """The instructor's view: every live seat's simulated chair of the class this page is in."""
        from pmk_nb.classroom import class_chairs

        settings = _class_settings()
        if settings is None:
            raise SettingsError("This page is not part of a class (no classroom settings).")
        members = [self._join(p, "class") for p in class_chairs(settings)]
        self._say(f"The class has {len(members)} chair{'s' if len(members) != 1 else ''} live.")
        return members

    def _join(self, profile: Any, source: str) -> FleetMember:
        if self.ctx.fleet is None:  # the first one: the page's own chair joins first, in control
            self.ctx.fleet = self.model
            own = self.ctx.profile()
            if own is not None:
                first = self.model.add(own)
                self.model.control(first.name)
                self.links.set_controlled(first.name)
                self._open(first)
                if not self.home.running:  # a fleet is live: the chair in control too (Home streams it)
                    self.home.start_preview()
        member = self.model.add(profile, source)
        self._open(member)
        return member

    def _open(self, member: FleetMember) -> None:
        if member.name in self.rows:
            return
        self.links.open(member)
        row = _Row(member)
        row.control.on_click(self._act(f"Taking control of {member.name}", lambda _b: self.take_control(member.name)))
        row.remove.on_click(self._act(f"Removing {member.name}", lambda _b: self.remove(member.name)))
        self.rows[member.name] = row
        self.rows_box.children = tuple(r.widget for r in self.rows.values())
        if not self._loop.running:
            self._loop.start()
        self.tick()

    # -- control ------------------------------------------------------------------------------------
    @needs_pin("Fleet")
    def take_control(self, name: object) -> float:
        """Make ``name`` the chair Home shows, drives and guides; returns the seconds the switch took.

        Driving the previous chair stops (Home's Drive toggle goes off, the deadman sends its zero);
        a goal it was given keeps running and stays in its row (:mod:`pmk_nb.ui.fleet.goals`), and
        comes back to Home with the chair.
        """
        if not isinstance(name, str):
            raise NotInFleet(str(name)[:80])
        member = self.model.get(name)
        old = self.model.controlled
        if old is not None and old.name == member.name:
            return 0.0
        started = time.perf_counter()
        self.home.stop_preview()
        if old is not None:
            self._goals[old.name] = park(self.home)
        self.model.control(member.name)
        self.links.set_controlled(member.name)
        resume(self.home, self._goals.pop(member.name, None))
        self.home.start_preview()
        self.switch_s = time.perf_counter() - started
        self._say(f"{member.name} is in control (switched in {self.switch_s * 1000:.0f} ms).")
        self.tick()
        return self.switch_s

    @needs_pin("Fleet")
    def remove(self, name: object) -> None:
        """Stop watching ``name``; the chair in control stays (give control to another first)."""
        if not isinstance(name, str):
            raise NotInFleet(str(name)[:80])
        member = self.model.get(name)
        controlled = self.model.controlled
        if controlled is not None and controlled.name == member.name:
            raise FleetError(f"{name} is in control.", hint="Give control to another chair first.")
        self.model.remove(name)
        self.links.close(name)
        self._goals.pop(name, None)
        row = self.rows.pop(name, None)
        if row is not None:
            self.rows_box.children = tuple(r.widget for r in self.rows.values())
            row.widget.close()
        self._refresh_choices()

    # -- rows and markers ----------------------------------------------------------------------------
    def statuses(self) -> list[ChairStatus]:
        """Every chair's row now, the chair in control first read (its map is the page's)."""
        members = self.model.members
        controlled = self.model.controlled
        first = self.links.status(controlled, self._goal_words(controlled.name)) if controlled is not None else None
        shown = self.links.map_key(first.name) if first is not None else None
        out = []
        for member in members:
            if first is not None and member.name == first.name:
                out.append(first)
            else:
                out.append(self.links.status(member, self._goal_words(member.name), shown))
        return out

    def tick(self) -> None:
        """Rows and markers from the links' latest (the panel's timer, ROWS_HZ)."""
        markers = []
        for status in self.statuses():
            row = self.rows.get(status.name)
            if row is not None:
                row.show(status)
            if status.pose is not None and status.same_map:
                radius = _footprint(self.model, status.name)
                markers.append(Marker(status.name, status.colour, *status.pose, status.controlled, radius))
        if self.layer.set_markers(markers) and not self.home.live.running:
            self.home.live.request_redraw()

    def _goal_words(self, name: str) -> str | None:
        """The row's goal: Home's (the chair in control), else the one parked with the chair."""
        controlled = self.model.controlled
        if controlled is not None and controlled.name == name:
            handle = ParkedGoals(None, self.home.goal.handle, None, self.home.rooms.handle).newest()
        else:
            parked = self._goals.get(name)
            handle = parked.newest() if parked is not None else None
        if handle is None:
            return None
        progress = handle.progress()
        left = f", {progress.remaining_m:.1f} m left" if progress.remaining_m is not None and not progress.done else ""
        x, y, _yaw = progress.goal
        return f"{progress.status.value.replace('_', ' ')} to ({x:.1f}, {y:.1f}){left}"

    # -- helpers ------------------------------------------------------------------------------------
    def _act(self, action: str, fn: Any) -> Any:
        def run(*args: Any) -> None:
            try:
                fn(*args)
            except Exception as err:
                if not isinstance(err, FleetError | SettingsError | ValueError):
                    log.exception("%s failed", action)
                self._say(error_text(err, action), "error")

        return run

    def _say(self, message: str, level: str = "info") -> None:
        colour = "#b00020" if level == "error" else "#1b5e20"
        self.note.value = f"<span style='color:{colour}'>{escape(message)}</span>" if message else ""
        if level == "error":
            self.ctx.notify(message, "error", inline=True)

    def close(self) -> None:
        """Stop the timer and close every fleet link but the one Home shows (the page's own chair)."""
        self._loop.stop()
        controlled = self.model.controlled
        self.links.close_all(keep=controlled.key if controlled is not None else None)
        if self.ctx.fleet is self.model:
            self.ctx.fleet = None


def _class_settings() -> Any:
    """The class this page's kernel is in (``PMK_CLASSROOM``), None outside a class or unreadable."""
    from pmk_nb.classroom import settings as classroom_settings

    try:
        return classroom_settings.from_env()
    except SettingsError:
        return None


def _footprint(model: Fleet, name: str) -> float:
    """The chair's footprint radius (m) from its profile; the Home default when it has none usable."""
    try:
        radius = float(model.get(name).profile.footprint_radius or 0.0)
    except (FleetError, TypeError, ValueError):
        radius = 0.0
    return radius if 0.0 < radius < 5.0 else 0.35
