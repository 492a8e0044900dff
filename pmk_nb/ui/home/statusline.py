"""Home's one status line over the map: where the chair is, how fast, and what it is doing.

The full texts (position, heading, zoom, laser) are one tap away in the Details card; this line is
what a rider reads at a glance (issue 28), so it stays short: a state word only when it is not
simply live, the room (else nothing), the speed, and what the chair is doing.
"""

from __future__ import annotations

import math
from typing import Any

from pmk_nb.ui.common.widgets import escape

_STATE_WORDS = {
    "off": "Preview off",
    "connecting": "Connecting…",
    "unreachable": "No connection",
}
STILL_MS = 0.03  # below this the chair is standing


def status_line(state: str, age: float | None, room: str | None, odom: Any, doing: str | None) -> str:
    """The line's HTML (escaped), e.g. ``In Kitchen · 0.42 m/s · Driving``."""
    parts: list[str] = []
    if state == "stale":
        parts.append(f"No data for {age:.0f} s" if age is not None and math.isfinite(age) else "No data")
    elif state in _STATE_WORDS:
        parts.append(_STATE_WORDS[state])
    if room:
        parts.append(f"In {room}")
    v = getattr(odom, "v", None) if state == "live" else None
    if isinstance(v, float) and math.isfinite(v):
        parts.append(f"{abs(v):.2f} m/s")
        if doing is None:
            doing = "Standing" if abs(v) < STILL_MS else "Moving"
    if doing and state == "live":
        parts.append(doing)
    css = "pmk-msg-warning" if state in ("stale", "unreachable") else "pmk-home-statusline-text"
    return f"<span class='{css}'>{escape(' · '.join(parts))}</span>" if parts else ""
