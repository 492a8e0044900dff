"""Home's drive panel: the joystick, a large Stop, slow mode, and what the chair is doing.

A **Drive** toggle in Home's toolbar (shown while the live preview runs: the preview's link is the
one that drives) shows the panel over the map; off, the map is free for tapping a destination and
nothing can drive. The page
side is :mod:`pmk_nb.ui.drive.script`; every message it posts lands in :meth:`DrivePanel._on_message`
on the kernel's thread and goes through :class:`pmk_nb.drive.DriveSession`, whose publisher
thread decides what reaches the chair. Texts are for the person in the chair: no jargon.

One driving page per chair (issue 30): each panel has a kernel-side id and a
:class:`pmk_nb.drive.DriveClaim` in the settings folder's ``drive/``, shared by every page's kernel.
Another page's panel shows "Driven from another page (since hh:mm)", its stick is refused (and
greyed), and **Take over driving** (tap twice) moves the claim; the previous driver's session stops
at its next tick. Stop on any page latches the chair-wide Stop until that page releases it (its
next press, or **Release the Stop**); a Stop whose page is gone is released only by an explicit
double tap on another page. Stop also cancels every navigation goal of the chair (issue 38: the
session calls ``ChairLink.stop_goals``; other pages' kernels cancel theirs through Home's
``stop_latch``). On a kiosk page with a PIN, **Take over driving** needs the PIN typed beside it
(Stop never does).
"""

from __future__ import annotations

import logging
import time
import uuid
from collections.abc import Callable
from datetime import datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.drive import ClaimView, DriveClaim, DriveSession, Hold, SpeedLimits, StopReason
from pmk_nb.errors import SettingsError
from pmk_nb.ui.common.widgets import TOUCH_PX, button
from pmk_nb.ui.drive.script import CHANNEL_CLASS, LANES, LOCKED_CLASS, PAD_HTML, PANEL_CLASS, page_html

if TYPE_CHECKING:
    from pmk_nb.chair import ChairProfile
    from pmk_nb.chair.link import ChairLink
    from pmk_nb.ui.kiosk.pin import KioskLock

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
    StopReason.OTHER_DRIVER: "Another page drives the chair.",
    StopReason.STOPPED_ELSEWHERE: "Stopped from another page.",
    StopReason.NO_CLAIM: "Stopped: cannot tell whether another page drives. Ask for help.",
}
CONFIRM_S = 5.0  # a second tap within this long confirms a take-over
#: the claim button's modes: (label, needs a confirming second tap)
CLAIM_ACTIONS = {
    "take": ("Take over driving", True),
    "release": ("Release the Stop", False),
    "force": ("Release the other page's Stop", True),
}


def hhmm(wall: float | None) -> str:
    return datetime.fromtimestamp(wall).strftime("%H:%M") if wall is not None else "?"


def claim_state(view: ClaimView | None) -> tuple[str | None, str | None]:
    """(status text, claim button mode) when the shared state keeps this page from driving."""
    if view is None:
        return None, None
    if view.hold is Hold.OTHER_DRIVER:
        if view.stop_by_me:
            return "Stopped from this page until you release it.", "release"
        return f"Driven from another page (since {hhmm(view.owner_since)}).", "take"
    if view.hold is Hold.STOPPED_ELSEWHERE:
        text = f"Stopped from another page (since {hhmm(view.stop_at)}) until released there."
        return text, (None if view.setter_live else "force")
    if view.hold is Hold.STOPPED_HERE:  # the stick's next press releases it too; goals need this button
        return None, "release"
    return None, None


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

    def __init__(
        self,
        on_stop: Callable[[StopReason], None] | None = None,
        *,
        claims_dir: Path | None = None,
        kiosk: KioskLock | None = None,
    ) -> None:
        self.on_stop = on_stop
        self.kiosk = kiosk  # a kiosk page: taking over driving needs the PIN (Stop never does)
        self.session: DriveSession | None = None
        self.member = uuid.uuid4().hex  # this page's id for the other pages: the kernel's, not the page's
        self.claims_dir = claims_dir
        self._armed: tuple[str, float] | None = None  # (claim mode, when) after a first tap
        self._locked = False
        self._offer: tuple[ChairLink, ChairProfile | None] | None = None
        self.toggle = w.ToggleButton(
            value=False, description="Drive", icon="gamepad", tooltip="Show the joystick to drive the chair by hand"
        )
        self.toggle.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="120px", display="none")
        self.toggle.add_class("pmk-drive-toggle")
        self.toggle.observe(self._on_toggle, names="value")
        self.pad = w.HTML(PAD_HTML)
        self.pad.add_class("pmk-drive-pad-box")
        # the stick's messages, in turn on each lane (drive_script.py: one update per widget in flight)
        self.lanes = [w.Text(value="", continuous_update=True, layout=w.Layout(display="none")) for _ in range(LANES)]
        for lane in self.lanes:
            lane.add_class(CHANNEL_CLASS)
            lane.observe(self._on_message, names="value")
        self.channel = self.lanes[0]
        self.stop_button = button("Stop", "pmk-drive-stop", icon="stop", style="danger", width="180px")
        self.stop_button.layout.height = "72px"
        self.stop_button.on_click(lambda _b: self.stop())
        self.slow = w.ToggleButton(value=False, description="Slow", icon="", tooltip="Drive at reduced speed")
        self.slow.layout = w.Layout(height="48px", width="180px")
        self.slow.add_class("pmk-drive-slow")
        self.slow.observe(self._on_slow, names="value")
        self.claim_button = button(CLAIM_ACTIONS["take"][0], "pmk-drive-claim", style="warning", width="180px")
        self.claim_button.layout.display = "none"
        self.claim_button.on_click(lambda _b: self.claim_action())
        # the kiosk PIN for Take over driving (shown with it on a kiosk page with a PIN)
        self.pin = w.Password(value="", placeholder="Kiosk PIN", layout=w.Layout(width="180px", display="none"))
        self.pin.add_class("pmk-drive-pin")
        self._pin_note = ""
        self.status = w.HTML(READY)
        self.status.add_class("pmk-drive-status")
        self.status.layout = w.Layout(max_width="180px")  # wraps under Stop and Slow (an inline style wins)
        self.page = w.Output(layout=w.Layout(display="none"))
        self.page.add_class("pmk-drive-page")
        self._page_shown = False
        self.widget = w.VBox(
            [self.stop_button, self.pad, self.slow, self.pin, self.claim_button, self.status, *self.lanes, self.page]
        )
        self.widget.add_class(PANEL_CLASS)
        self.widget.add_class("pmk-drive-right")
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
        self.toggle.icon = "gamepad"  # pressed look shows on; the icon is its only label on a phone
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
        folder = self.claims_dir
        if folder is None:
            from pmk_nb.chair import config_dir

            folder = config_dir() / "drive"
        claim = DriveClaim(folder, link.host, link.port, member=self.member)
        self.session = DriveSession(link, limits_of(profile), topic=topic, on_stop=self.on_stop, claim=claim).start()
        self.session.slow = bool(self.slow.value)
        self.status.value = READY
        self.dock(getattr(profile, "drive_hand", "right"))
        self.widget.layout.display = "flex"
        return self.session

    def dock(self, hand: object) -> str:
        """Dock the panel at the rider's side of the map ("left" or "right"; anything else: right)."""
        side = "left" if hand == "left" else "right"
        self.widget.remove_class(f"pmk-drive-{'right' if side == 'left' else 'left'}")
        self.widget.add_class(f"pmk-drive-{side}")
        return side

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
        view = session.claim_view
        text, mode = claim_state(view)
        if session.driving:
            text, mode = DRIVING + (" (slow)" if session.slow else ""), None
        elif text is None:
            cause = session.gate.last_stop
            text = STOPPED[cause] if cause is not None else READY
        if mode == "take" and self._pin_note:
            text = f"{text} {self._pin_note}"
        if self.status.value != text:
            self.status.value = text
        locked = view is not None and not view.may_drive
        if locked != self._locked:  # greyed and inert on the page; the kernel refuses it anyway
            self._locked = locked
            (self.pad.add_class if locked else self.pad.remove_class)(LOCKED_CLASS)
        self._show_claim_button(mode)

    def doing(self) -> str | None:
        """A word for Home's status line while the stick drives (None otherwise)."""
        session = self.session
        if session is None or not session.driving:
            return None
        return "Driving (slow)" if session.slow else "Driving"

    def needs_pin(self) -> bool:
        """Taking over needs the kiosk PIN here: a kiosk page with a PIN set."""
        return self.kiosk is not None and self.kiosk.pins.is_set()

    def _show_claim_button(self, mode: str | None) -> None:
        pin_display = "" if mode == "take" and self.needs_pin() else "none"
        if self.pin.layout.display != pin_display:
            self.pin.layout.display = pin_display
        if mode != "take":
            self._pin_note = ""
        armed = self._armed
        if armed is not None and (armed[0] != mode or time.monotonic() - armed[1] > CONFIRM_S):
            self._armed = armed = None
        label = "Tap again to confirm" if armed is not None else CLAIM_ACTIONS[mode][0] if mode else ""
        if self.claim_button.description != label:
            self.claim_button.description = label
        display = "" if mode else "none"
        if self.claim_button.layout.display != display:  # in Slow's place: this page cannot drive now
            self.claim_button.layout.display = display
            self.slow.layout.display = "none" if mode else ""

    def claim_action(self) -> None:
        """The claim button: what it does is decided from the shared state now, not from the page
        (a page can click a hidden button); a take-over or a forced release needs a second tap."""
        session = self.session
        if session is None or session.claim is None:
            return
        try:
            _text, mode = claim_state(session.claim.view())
        except OSError as err:
            log.warning("reading the drive claim failed: %s", err)
            return
        if mode == "take" and self.needs_pin():
            self._armed = None
            self._take_with_pin(session)
        elif mode is None:
            self._armed = None
        elif CLAIM_ACTIONS[mode][1] and (
            self._armed is None or self._armed[0] != mode or time.monotonic() - self._armed[1] > CONFIRM_S
        ):
            self._armed = (mode, time.monotonic())
        else:
            self._armed = None
            try:
                if mode == "take":
                    session.take_over()
                else:
                    session.release_stop(force=mode == "force")
            except OSError as err:  # the shared folder went away: nothing changes, nothing drives
                log.warning("changing the drive claim failed: %s", err)
        self.refresh()

    def _take_with_pin(self, session: DriveSession) -> None:
        """Take over on a kiosk page: the PIN typed beside the button, checked by the kernel (the
        wrong tries count with the kiosk's, and lock out alike); the typed PIN is cleared either way."""
        assert self.kiosk is not None
        typed = str(self.pin.value or "").strip()
        self.pin.value = ""
        if not typed:
            self._pin_note = "Type the kiosk PIN, then tap Take over driving."
            return
        try:
            answer = self.kiosk.pins.check(typed)
        except SettingsError as err:
            self._pin_note = str(err)
            return
        if answer.wait_s > 0:
            self._pin_note = f"Too many wrong PINs: try again in {answer.wait_s:.0f} s."
        elif not answer.ok:
            self._pin_note = "Wrong PIN."
        else:
            self._pin_note = ""
            try:
                session.take_over()
            except OSError as err:
                log.warning("changing the drive claim failed: %s", err)

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
