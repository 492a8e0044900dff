"""What the Home screen says: connection state, position, speed, zoom, and its warnings.

Pure functions of a :class:`PreviewSnapshot` (the preview's chair link state and latest messages,
taken by :class:`pmk_nb.ui.home.preview.PreviewController`), so the texts and the "no data
for N s" rule are tested without a page or a chair; :class:`pmk_nb.ui.home.screen.HomeScreen` only copies
them into its HTML widgets.  All user-facing text of the Home screen is made here.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pmk_nb.chair import BLIND_KINDS, NO_RETURN, UNKNOWN, Odometry, Pose2D, Scan, blind_ahead
from pmk_nb.errors import ChairLinkError
from pmk_nb.ui.common.widgets import escape
from pmk_nb.viewport import explain_nulls, mounted

if TYPE_CHECKING:  # the link package pulls in roslibpy: imported when a preview starts, not before
    from pmk_nb.chair.link import LinkState
    from pmk_nb.grid import OccupancyGrid

NO_VALUE = "—"  # shown instead of a value that is not current
STALE_AFTER = 2.0  # s without odometry before the "no data" state
CONNECT_TIMEOUT = 5.0  # s the preview waits for the chair's rosbridge
#: A run of blind laser rays across the chair's heading at least this wide (degrees) is reported.
BLIND_AHEAD_MIN_DEG = 5.0

_STATE_TEXTS = {
    "off": "Preview stopped",
    "connecting": "Connecting to the chair…",
    "live": "Live",
    "unreachable": "Chair unreachable",
}


@dataclass(frozen=True)
class PreviewSnapshot:
    """The preview's link at one refresh.

    Attributes:
        link_state: the link's state; None when the preview is stopped (no link).
        odom: the latest odometry.
        pose: the latest pose from the profile's pose source, else the odometry.
        connect_error: why connecting failed, if it did.
        started: ``time.monotonic()`` when the preview started.
        scan: the latest laser scan.
    """

    link_state: LinkState | None
    odom: Odometry | None = None
    pose: Pose2D | Odometry | None = None
    connect_error: str | None = None
    started: float = 0.0
    scan: Scan | None = None


STOPPED = PreviewSnapshot(None)


@dataclass(frozen=True)
class InfoTexts:
    """HTML for each line of the panel; ``status`` None means "leave the page's status line as is"."""

    state: str
    position: str
    speed: str
    zoom: str
    status: str | None
    laser: str = ""
    #: the laser's safety alerts behind ``laser`` ("blind", "touching"), for the live region
    alerts: frozenset[str] = frozenset()


def whole_degrees(radians: float) -> str:
    """Radians as whole degrees, never "-0" (a heading of -0.2° is shown as 0°, not -0°)."""
    text = f"{math.degrees(radians):.0f}"
    return "0" if text == "-0" else text


def connection_state(snap: PreviewSnapshot, now: float | None = None) -> tuple[str, float | None]:
    """("off"|"connecting"|"live"|"stale"|"unreachable", seconds since the last odometry or None).

    "stale" when the link says so (``LinkState.STALE``, a str enum) or odometry stopped coming.
    """
    if snap.link_state is None:
        return "off", None
    if snap.connect_error is not None:
        return "unreachable", None
    now = time.monotonic() if now is None else now
    odom = snap.odom
    age = now - float(odom.received) if odom is not None else None
    if snap.link_state == "stale" or (age is not None and age > STALE_AFTER):
        return "stale", age
    if odom is None:
        waited = now - snap.started
        return ("stale", waited) if waited > STALE_AFTER + CONNECT_TIMEOUT else ("connecting", None)
    return "live", age


def laser_reading(
    scan: Scan | None, grid: OccupancyGrid | None = None, pose: Pose2D | Odometry | None = None
) -> tuple[str, frozenset[str]]:
    """The panel's laser line and the laser's safety alerts ("blind", "touching") from one reading.

    The panel's line and the screen reader's live region (:mod:`pmk_nb.ui.home.live_region`) share it, so
    what is said is what is shown. The forward direction is taken as the laser's 0° (the scanner's
    mounting yaw is not applied). With the map and the chair's pose, a ``null`` ray along which the
    map shows no wall within the laser's range is the expected "nothing there" (a long corridor), not
    blindness (:func:`pmk_nb.viewport.mapcast.explain_nulls`); without them every null counts.
    """
    if scan is None or scan.kinds is None or scan.kinds.size == 0:
        return "", frozenset()
    angles = scan.angles()
    origin = None if pose is None else mounted((float(pose.x), float(pose.y), float(pose.theta)), scan.mount)
    kinds = scan.kinds
    # only the forward half is cast (the warning is about what is ahead): half the work when all is null
    nulls = (kinds == UNKNOWN) & (np.abs(np.angle(np.exp(1j * angles))) <= math.pi / 2)
    seen = explain_nulls(nulls, angles, grid, origin, float(scan.range_min), float(scan.range_max))
    if seen.any():
        kinds = np.where(seen, NO_RETURN, kinds).astype(np.uint8)
    sector = blind_ahead(kinds, angles)
    blind = int(np.isin(kinds, BLIND_KINDS).sum())
    parts, alerts = [], set()
    if sector.too_close:
        touching = f"Something is touching the chair ahead ({sector.too_close} rays)"
        parts.append(f"<span class='pmk-msg-warning'>{touching}</span>")
        alerts.add("touching")
    if sector.degrees >= BLIND_AHEAD_MIN_DEG:
        parts.append(f"<span class='pmk-msg-warning'>Laser blind ahead, {sector.degrees:.0f}°</span>")
        alerts.add("blind")
    if not parts:
        parts.append(escape(f"Laser: {scan.kinds.size} rays, {blind} unknown"))
    return "<br>".join(parts), frozenset(alerts)


def laser_text(scan: Scan | None, grid: OccupancyGrid | None = None, pose: Pose2D | Odometry | None = None) -> str:
    """The panel's laser line (see :func:`laser_reading`)."""
    return laser_reading(scan, grid, pose)[0]


def laser_alerts(
    scan: Scan | None, grid: OccupancyGrid | None = None, pose: Pose2D | Odometry | None = None
) -> frozenset[str]:
    """The laser's safety alerts now (see :func:`laser_reading`): the live region says each when it appears."""
    return laser_reading(scan, grid, pose)[1]


def info_texts(
    state: str,
    age: float | None,
    pose: Pose2D | Odometry | None,
    odom: Odometry | None,
    zoom: int,
    zoom_factor: float,
    scan: Scan | None = None,
    grid: OccupancyGrid | None = None,
) -> InfoTexts:
    """The panel's lines for one refresh (all escaped HTML)."""
    stale = state in ("stale", "unreachable")
    laser, alerts = laser_reading(scan if state == "live" else None, grid, pose)
    if pose is not None:
        # say which frame the position is in: the map (tf, AMCL) or odometry (which drifts); Home
        # falls back to odometry while the chosen pose source sends nothing
        frame = pose.frame or "odom"
        pos = f"x {pose.x:.2f} m, y {pose.y:.2f} m, heading {whole_degrees(pose.theta)}° ({frame} frame)"
        if stale:  # where the chair was, not where it is: say so and grey it
            pos = f"Last known: {pos}"
    else:
        pos = f"Position: {NO_VALUE}"
    # a speed is only true while data flows: during a stall it would claim the chair still moves
    if odom is not None and not stale:
        speed = f"Speed: {odom.v:.2f} m/s, turning {whole_degrees(odom.w)}°/s"
    else:
        speed = f"Speed: {NO_VALUE}"
    if state == "stale":
        state_text = f"No data for {age:.0f} s" if age is not None else "No data"
    else:
        state_text = _STATE_TEXTS[state]
    css = {"live": "info", "off": "info", "connecting": "info"}.get(state, "warning")
    status: str | None = None
    if state == "stale":
        status = (
            f"<span class='pmk-msg-warning'>No data from the chair for {age or 0:.0f} s: "
            "check that it is switched on and in range.</span>"
        )
    elif state in ("live", "off"):
        status = ""
    return InfoTexts(
        state=f"<span class='pmk-msg-{css}'>{escape(state_text)}</span>",
        position=_greyed(escape(pos), stale and pose is not None),
        speed=_greyed(escape(speed), stale),
        zoom=escape(f"Zoom: {zoom} (x{zoom_factor:.2g})"),
        status=status,
        laser=laser,
        alerts=alerts,
    )


def _greyed(html: str, grey: bool) -> str:
    return f"<span class='pmk-stale'>{html}</span>" if grey else html


#: Home before Preview when no map was sent from here: the chair's map comes with the preview (issue 40:
#: the page was blank, with no word of what to do).
PRESS_PREVIEW_TEXT = "No map was sent from this dashboard: press Preview to see the map the chair uses."


def hint_html(message: str) -> str:
    """A hint line for the page ("" for none)."""
    return f"<div class='pmk-msg-info pmk-home-hint'>{escape(message)}</div>" if message else ""


def warning_html(message: str) -> str:
    """A warning line for the page ("" for no warning)."""
    return f"<div class='pmk-msg-warning'>⚠ {escape(message)}</div>" if message else ""


def unreachable_text(err: BaseException, host: str, port: int) -> str:
    """Why the preview's chair cannot be reached, naming its address once.

    A :class:`ChairLinkError` that carries the chair's address (``host``) was worded by the link,
    which names the address itself; any other failure gets it added here.
    """
    if isinstance(err, ChairLinkError) and err.host is not None:
        return f"The chair is unreachable: {err}"
    return f"The chair at {host}:{port} is unreachable: {err}"


def chair_silent_text(host: str, port: int, problem: str) -> str:
    """The up-front warning when the chair's rosbridge port does not answer a probe."""
    return (
        f"The chair at {host}:{port} does not answer ({problem}). Check that it is switched on, "
        "that this device is on the chair's network, and the Settings screen."
    )


NO_PROFILE_TEXT = "No wheelchair configured yet: fill in and save the Settings screen."
