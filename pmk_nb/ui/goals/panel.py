"""Home's destination panel: "Set destination", the goal's status and remaining distance, Cancel.

With "Set destination" on, a tap on the live map sets the goal and a drag from it gives the
heading (:mod:`pmk_nb.ui.goals.picker`); the mode turns itself off after one goal, so a drag pans
the map again. The goal goes to the chair through :meth:`ChairLink.navigate_to` (Nav2, move_base or
the goal topic, detected) on a worker thread; the status words are the handle's (accepted, moving,
arrived, aborted, cancelled, rejected, and what the link cannot know: link lost, no answer, cancel
not honoured, outcome unknown), worded in :mod:`pmk_nb.chair.link.goals.goal_words`, plus a line when the
chair has been silent or a cancel awaits its confirmation. The texts refresh with Home's info panel
(:meth:`tick`).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.chair.link import GoalLink, GoalStatus
from pmk_nb.chair.link import goal_words as words
from pmk_nb.errors import PmkError
from pmk_nb.speech import phrases
from pmk_nb.ui.common.widgets import TOUCH_PX, button, escape
from pmk_nb.ui.goals.picker import Goal, GoalOverlay, GoalPicker

if TYPE_CHECKING:
    from pmk_nb.chair.link import GoalHandle, GoalProgress
    from pmk_nb.ui.live.view import LiveView

log = logging.getLogger(__name__)


def status_html(
    goal: Goal | None,
    progress: GoalProgress | None,
    note: str = "",
    *,
    cancel_pending: bool = False,
    elsewhere: str | None = None,
) -> str:
    """The panel's text: the goal, its status word, the metres left and the route's message; then a
    warning when the chair has been silent, and "cancel sent" while a cancel awaits confirmation.

    ``note`` is plain text (an error's words can quote a server or a file), escaped here.
    ``elsewhere`` names the room a Go to… is driving to: with no tapped goal running, the panel says
    so instead of "No destination" (the chair has one; the rooms panel shows its progress).
    """
    idle = goal is None or (progress is not None and progress.done)
    if elsewhere and idle:
        return f"Going to <b>{escape(elsewhere)}</b> (Go to…)."
    if goal is None:
        if note:
            return escape(note)
        return "No destination. Press <b>Set destination</b>, then tap the map (drag to set the heading)."
    where = f"Destination ({goal[0]:.2f}, {goal[1]:.2f})"
    if progress is None:
        return f"{where}: <b class='pmk-goal-word'>sending</b>{escape(note)}"
    left = "" if progress.remaining_m is None else f", {progress.remaining_m:.1f} m to go"
    state = progress.status.value
    word = words.STATUS_WORDS.get(state, state)
    extra = ""
    if progress.quiet_s is not None and not progress.done:
        extra += f"<br><b class='pmk-goal-quiet pmk-warn'>{escape(words.quiet(progress.quiet_s))}</b>"
    if cancel_pending and not progress.done:
        extra += f"<br><small class='pmk-goal-cancel-sent'>{escape(words.cancel_sent())}</small>"
    warn = " pmk-warn" if progress.status in _WARN else ""
    return (
        f"{where}: <b class='pmk-goal-word{warn}' data-status='{state}'>{word}</b>{left}"
        f"<br><small>{escape(progress.message)}</small>{extra}"
    )


_WARN = (GoalStatus.LINK_LOST, GoalStatus.NO_ANSWER, GoalStatus.CANCEL_IGNORED, GoalStatus.UNKNOWN)


class GoalPanel:
    """The widgets and the goal they follow; ``widget`` goes under the map."""

    def __init__(self, live: LiveView, *, on_error: Callable[[str], None] | None = None) -> None:
        self.live = live
        self.on_error = on_error
        # spoken feedback (Home wires it to the rooms guide's phrase queue): a (key, text) phrase
        self.speak: Callable[[tuple[str, str]], object] | None = None
        self._spoken: GoalHandle | None = None  # the handle whose ending was said
        self.link: GoalLink | None = None
        self.handle: GoalHandle | None = None
        self.goal: Goal | None = None
        self._chair: tuple[float, float] | None = None
        self._note = ""
        self._elsewhere: str | None = None  # the room a Go to… drives to (Home's tick says)
        self._stopped = False  # a Stop holds for this chair (any page's): no destination (issue 38)
        self.picker = GoalPicker(lambda: live.viewport, lambda: self._chair, self.send, self._redraw)
        self.overlay = GoalOverlay(self.picker)
        live.overlays.append(self.overlay)
        self.toggle = w.ToggleButton(value=False, description="Set destination", icon="map-marker")
        self.toggle.tooltip = "Then tap the map where the chair should go; drag from there to set its heading"
        self.toggle.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="180px")
        self.toggle.add_class("pmk-goal-set")
        self.cancel_button = button("Cancel", "pmk-goal-cancel", icon="stop", style="danger")
        self.cancel_button.layout.display = "none"
        self.status = w.HTML(status_html(None, None))
        self.status.add_class("pmk-goal-status")
        self.widget = w.VBox([w.HBox([self.toggle, self.cancel_button]), self.status])
        self.widget.add_class("pmk-goal-panel")
        self.toggle.observe(self._on_toggle, names="value")
        self.cancel_button.on_click(lambda _b: self.cancel())
        self.attach(None)

    def attach(self, link: GoalLink | None) -> None:
        """The chair link goals go to (None: no preview running, nothing can be sent)."""
        self.link = link
        self._enable()

    def set_stopped(self, stopped: bool) -> None:
        """A Stop holds for this chair (Home's tick): Set destination is greyed and refused."""
        if stopped != self._stopped:
            self._stopped = stopped
            self._enable()
            self.refresh()

    def _enable(self) -> None:
        off = self.link is None or self._stopped
        self.toggle.disabled = off
        if off and self.toggle.value:
            self.toggle.value = False

    def _on_toggle(self, change: dict[str, Any]) -> None:
        on = change.get("new") is True  # front-end value: anything but a real True is off
        if on and (self._stopped or self.link is None):  # a page can click a greyed button
            self.toggle.value = False
            return
        gestures = self.live.gestures
        gestures.picker = self.picker if on and self.link is not None else None
        if not on:
            self.picker.abort()
        self.toggle.icon = "map-marker"  # pressed look shows on; the icon is its only label on a phone

    def _redraw(self) -> None:
        self.overlay.changed()

    def send(self, goal: Goal) -> None:
        """Send ``goal`` to the chair on a worker thread (route detection asks rosapi)."""
        self.toggle.value = False
        link = self.link
        if link is None:
            return
        self.goal, self.handle, self._note = goal, None, ""
        self.overlay.set_goal(goal)
        self._say(phrases.destination_set("the destination"))
        threading.Thread(target=self._send, args=(link, goal), daemon=True, name="pmk-goal-send").start()
        self.refresh()

    def _send(self, link: GoalLink, goal: Goal) -> None:
        try:
            handle = link.navigate_to(*goal)
        except (PmkError, OSError) as err:
            self._note = f" — not sent: {err}"
            self.goal = None
            self.overlay.set_goal(None)
            if self.on_error is not None:
                self.on_error(f"The destination was not sent: {err}")
            return
        if self.goal == goal:  # not replaced meanwhile
            self.handle = handle

    def cancel(self) -> None:
        handle = self.handle
        if handle is not None:
            handle.cancel()
        self.refresh()

    def tick(self, pose: Any, elsewhere: str | None = None) -> None:
        """Home's info refresh: remember the chair's position and the room a Go to… drives to, update
        the texts."""
        x, y = getattr(pose, "x", None), getattr(pose, "y", None)
        self._chair = (float(x), float(y)) if isinstance(x, float) and isinstance(y, float) else None
        self._elsewhere = elsewhere
        if elsewhere:  # a Go to… replaced a finished tapped goal: once it ends, that goal is not shown again
            self.forget_finished()
        self.refresh()

    def forget_finished(self) -> None:
        """Drop a tapped goal that has ended (or failed to send), so the panel never shows it as the
        destination again after a later Go to… or a new map (issue 40); a running one is kept."""
        handle = self.handle
        progress = handle.progress() if handle is not None else None
        if self._note or (progress is not None and progress.done):
            self.goal, self.handle, self._note = None, None, ""
            self.overlay.set_goal(None)

    def refresh(self) -> None:
        handle = self.handle
        progress = handle.progress() if handle is not None else None
        pending = handle is not None and handle.cancel_requested and handle.cancel_honoured is None
        pending = pending and progress is not None and progress.status is not GoalStatus.CANCEL_IGNORED
        text = status_html(self.goal, progress, self._note, cancel_pending=pending, elsewhere=self._elsewhere)
        if self._stopped:  # any page's Stop holds: say why Set destination is greyed
            text += f"<br><b class='pmk-goal-stopped pmk-warn'>{escape(words.stop_latched())}</b>"
        self.status.value = text
        active = self.goal is not None and (progress is None or not progress.done) and not self._note
        self.cancel_button.layout.display = "" if active else "none"
        if progress is not None and progress.done and self.overlay.goal is not None:
            self.overlay.set_goal(None)  # the arrow goes; the text says how it ended
        if progress is not None and progress.done and handle is not self._spoken:
            self._spoken = handle
            ending = _ending(progress.status)
            if ending is not None:  # an unknown outcome is shown, not announced
                self._say(ending)

    def doing(self) -> str | None:
        """A word for Home's status line while a tapped destination's goal runs (None otherwise)."""
        handle = self.handle
        progress = handle.progress() if handle is not None else None
        if self.goal is None or self._note or (progress is not None and progress.done):
            return None
        return "Going to the destination"

    def _say(self, phrase: tuple[str, str]) -> None:
        if self.speak is not None:
            self.speak(phrase)


def _ending(status: GoalStatus) -> tuple[str, str] | None:
    """What is said when a tapped destination's goal ends (None: nothing certain to say)."""
    if status is GoalStatus.UNKNOWN:
        return None
    if status is GoalStatus.ARRIVED:
        return phrases.arrived("the destination")
    if status is GoalStatus.CANCELLED:
        return phrases.stopped("cancel")
    return phrases.goal_failed("the destination")
