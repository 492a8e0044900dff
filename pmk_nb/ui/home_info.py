"""What the Home screen's information panel says: connection state, position, speed, zoom.

Pure functions of the chair link's latest messages (no widgets), so the texts and the "no data
for N s" rule are tested without a page; :class:`pmk_nb.ui.home.HomeScreen` only copies them into
its HTML widgets.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

from pmk_nb.ui.widgets import escape

STALE_AFTER = 2.0  # s without odometry before the "no data" state
CONNECT_TIMEOUT = 5.0  # s the preview waits for the chair's rosbridge

_STATE_TEXTS = {
    "off": "Preview stopped",
    "connecting": "Connecting to the chair…",
    "live": "Live",
    "unreachable": "Chair unreachable",
}


@dataclass(frozen=True)
class InfoTexts:
    """HTML for each line of the panel; ``status`` None means "leave the page's status line as is"."""

    state: str
    position: str
    speed: str
    zoom: str
    status: str | None


def connection_state(
    link: Any, error: str | None, started: float, now: float | None = None
) -> tuple[str, float | None]:
    """("off"|"connecting"|"live"|"stale"|"unreachable", seconds since the last odometry or None).

    Args:
        link: the preview's chair link (None when the preview is stopped).
        error: why connecting failed, if it did.
        started: ``time.monotonic()`` when the preview started.
    """
    if link is None:
        return "off", None
    if error is not None:
        return "unreachable", None
    now = time.monotonic() if now is None else now
    odom = call(link, "latest_odom")
    age = now - float(odom.received) if odom is not None else None
    state = str(getattr(getattr(link, "state", None), "value", getattr(link, "state", ""))).lower()
    if state.endswith("stale") or (age is not None and age > STALE_AFTER):
        return "stale", age
    if odom is None:
        waited = now - started
        return ("stale", waited) if waited > STALE_AFTER + CONNECT_TIMEOUT else ("connecting", None)
    return "live", age


def info_texts(state: str, age: float | None, pose: Any, odom: Any, zoom: int, zoom_factor: float) -> InfoTexts:
    """The panel's lines for one refresh (all escaped HTML)."""
    if pose is not None:
        # say which frame the position is in: the map (tf, AMCL) or odometry (which drifts); Home
        # falls back to odometry while the chosen pose source sends nothing
        frame = getattr(pose, "frame", None) or "odom"
        pos = f"x {pose.x:.2f} m, y {pose.y:.2f} m, heading {math.degrees(pose.theta):.0f}° ({frame} frame)"
    else:
        pos = "Position: –"
    speed = f"Speed: {odom.v:.2f} m/s, turning {math.degrees(odom.w):.0f}°/s" if odom is not None else "Speed: –"
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
        position=escape(pos),
        speed=escape(speed),
        zoom=escape(f"Zoom: {zoom} (x{zoom_factor:.2g})"),
        status=status,
    )


def note(message: str) -> str:
    """A warning line for the page."""
    return f"<div class='pmk-msg-warning'>⚠ {escape(message)}</div>"


def set_html(widget: Any, value: str) -> None:
    """Assign only when changed: each assignment is a message to the page."""
    if widget.value != value:
        widget.value = value


def call(obj: Any, name: str) -> Any:
    """``obj.name()``, or None when that fails (a link going away mid-refresh)."""
    try:
        return getattr(obj, name)()
    except Exception:
        return None


def subscribe_state(link: Any, cb: Any) -> Any:
    """``link.on_state_change(cb)`` when the link has it; returns the unsubscribe callable or None."""
    subscribe = getattr(link, "on_state_change", None)
    if subscribe is None:
        return None
    try:
        return subscribe(cb)
    except Exception:
        return None
