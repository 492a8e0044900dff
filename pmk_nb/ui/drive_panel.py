"""Home's drive panel: the joystick, a large Stop, slow mode, and what the chair is doing.

A **Drive** toggle in Home's toolbar (shown while the live preview runs: the preview's link is the
one that drives) shows the panel over the map; off, the map is free for tapping a destination and
nothing can drive. The page
side is :mod:`pmk_nb.ui.drive_script`; every message it posts lands in :meth:`DrivePanel._on_message`
on the kernel's thread and goes through :class:`pmk_nb.drive.DriveSession`, whose publisher
thread decides what reaches the chair. Texts are for the person in the chair: no jargon.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.drive import DriveSession, SpeedLimits, StopReason
from pmk_nb.ui.drive_script import CHANNEL_CLASS, PAD_HTML, page_html
from pmk_nb.ui.widgets import TOUCH_PX, button

if TYPE_CHECKING:
    from pmk_nb.chair.link.client import ChairLink
    from pmk_nb.chair.profiles import ChairProfile

log = logging.getLogger(__name__)

READY = "Hold the stick to drive. Let go to stop."
DRIVING = "Driving."
STOPPED: dict[StopReason, str] = {
    StopReason.RELEASED: READY,
    StopReason.STOP_BUTTON: "Stopped. Press the stick again to drive.",
    StopReason.HIDDEN: "Stopped: the page was hidden. Press the stick again to drive.",
    StopReason.KEEPALIVE: "Stopped: the connection is too slow. Lift your finger and press again.",
    StopReason.LINK: "Stopped: no news from the chair. Wait for Live, then press again.",
    StopReason.CLOSED: READY,
}


def limits_of(profile: ChairProfile | None) -> SpeedLimits:
    """The profile's speed limits; the defaults when there is no (usable) profile."""
    if profile is None:
        return SpeedLimits()
    try:
        return SpeedLimits(profile.max_linear, profile.max_angular, profile.slow_factor)
    except (TypeError, ValueError) as err:  # a profile saved by hand with nonsense: drive gently
        log.warning("speed limits of %s unusable (%s): using the defaults", profile.name, err)
        return SpeedLimits()


class DrivePanel:
    """The widgets and their wiring; :meth:`attach` a link to drive, :meth:`detach` to stop."""

    def __init__(self, on_stop: Callable[[StopReason], None] | None = None) -> None:
        self.on_stop = on_stop
        self.session: DriveSession | None = None
        self._offer: tuple[ChairLink, ChairProfile | None] | None = None
        self.toggle = w.ToggleButton(
            value=False, description="Drive", icon="gamepad", tooltip="Show the joystick to drive the chair by hand"
        )
        self.toggle.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="120px", display="none")
        self.toggle.add_class("pmk-drive-toggle")
        self.toggle.observe(self._on_toggle, names="value")
        self.pad = w.HTML(PAD_HTML)
        self.pad.add_class("pmk-drive-pad-box")
        self.channel = w.Text(value="", continuous_update=True, layout=w.Layout(display="none"))
        self.channel.add_class(CHANNEL_CLASS)
        self.channel.observe(self._on_message, names="value")
        self.stop_button = button("Stop", "pmk-drive-stop", icon="stop", style="danger", width="180px")
        self.stop_button.layout.height = "72px"
        self.stop_button.on_click(lambda _b: self.stop())
        self.slow = w.ToggleButton(value=False, description="Slow", icon="", tooltip="Drive at reduced speed")
        self.slow.layout = w.Layout(height="48px", width="180px")
        self.slow.add_class("pmk-drive-slow")
        self.slow.observe(self._on_slow, names="value")
        self.status = w.HTML(READY)
        self.status.add_class("pmk-drive-status")
        self.status.layout = w.Layout(max_width="180px")  # wraps under Stop and Slow (an inline style wins)
        self.page = w.Output(layout=w.Layout(display="none"))
        self.page.add_class("pmk-drive-page")
        self._page_shown = False
        self.widget = w.VBox([self.stop_button, self.pad, self.slow, self.status, self.channel, self.page])
        self.widget.add_class("pmk-drive")
        self.widget.layout.display = "none"

    # -- life ------------------------------------------------------------------------------------
    def offer(self, link: ChairLink | None, profile: ChairProfile | None) -> None:
        """Make driving ``link`` possible (the Drive toggle shows); None hides the toggle and stops."""
        self._offer = (link, profile) if link is not None else None
        if link is None:
            self.toggle.value = False  # driving resumes only when someone asks for it again
            self.detach()
        elif self.toggle.value:
            self.attach(link, profile)
        self.toggle.layout.display = "" if link is not None else "none"

    def _on_toggle(self, change: dict[str, Any]) -> None:
        on = change.get("new") is True
        self.toggle.icon = "check" if on else "gamepad"
        if on and self._offer is not None:
            self.attach(*self._offer)
        else:
            self.detach()

    def attach(self, link: ChairLink, profile: ChairProfile | None) -> DriveSession:
        """Drive ``link`` with the profile's limits and velocity topic; shows the panel."""
        self.detach()
        if not self._page_shown:  # once per panel: the script binds every pad the page ever shows
            from IPython.display import HTML

            self.page.append_display_data(HTML(page_html()))
            self._page_shown = True
        topic = profile.cmd_vel_topic if profile is not None else None
        self.session = DriveSession(link, limits_of(profile), topic=topic, on_stop=self.on_stop).start()
        self.session.slow = bool(self.slow.value)
        self.status.value = READY
        self.widget.layout.display = "flex"
        return self.session

    def detach(self) -> None:
        """Stop the chair if it is driving (one zero), end the publisher, hide the panel."""
        session, self.session = self.session, None
        if session is not None:
            session.close()
        self.widget.layout.display = "none"

    def stop(self) -> None:
        """The Stop button: zero now, and this press drives no more."""
        session = self.session
        if session is not None:
            session.stop()
        self.status.value = STOPPED[StopReason.STOP_BUTTON]

    def refresh(self) -> None:
        """The status line from the session (called by Home's info loop, a few times a second)."""
        session = self.session
        if session is None:
            return
        if session.driving:
            text = DRIVING + (" (slow)" if session.slow else "")
        else:
            cause = session.gate.last_stop
            text = STOPPED[cause] if cause is not None else READY
        if self.status.value != text:
            self.status.value = text

    # -- callbacks (kernel thread) -------------------------------------------------------------------
    def _on_message(self, change: dict[str, Any]) -> None:
        session = self.session
        if session is not None:
            session.feed(change.get("new"))

    def _on_slow(self, change: dict[str, Any]) -> None:
        value = change.get("new") is True
        self.slow.icon = "check" if value else ""
        if self.session is not None:
            self.session.slow = value
