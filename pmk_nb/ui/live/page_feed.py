"""The kernel's side of the page-drawn chair (issue 41): recent poses and the view, as small JSON.

The kernel keeps drawing the map, the laser and the overlays on the ipycanvas; the chair's marker is
drawn by the page (:mod:`pmk_nb.ui.live.page_script`) at the display's rate, interpolated between
the poses this feed sends (:mod:`pmk_nb.viewport.glide`).  The feed is a hidden Text widget whose
value the page reads: no custom widget, nothing to install (as the drive stick's channels).

Each message: ``id`` (which canvas), ``seq`` (the kernel's frames drawn so far), ``now`` (kernel
clock, s), ``next`` (the next message comes within this many seconds: one tick while the chair
moves, :data:`~pmk_nb.viewport.glide.HEARTBEAT_S` while it is parked, ``null`` when the view is not
running), ``behind`` (how far back
the page draws), ``poses`` (``[t, x, y, yaw, v]``, oldest first), ``px`` (``[ax, bx, ay, by]``, the
view's world -> canvas pixel map), ``r`` / ``dot`` (the chair's and heading dot's radii, canvas px),
``m`` (the footprint's radius, m), ``stale`` (no fresh data: the page draws it grey).
"""

from __future__ import annotations

import itertools
import json
from collections import deque
from typing import Any

import ipywidgets as w

from pmk_nb.viewport import FEED_POSES, HEARTBEAT_S, StampedPose, Viewport, pixel_affine

FEED_CLASS = "pmk-live-feed"
_IDS = itertools.count(1)


class PageFeed:
    """The hidden Text widget the page reads, and what goes into it."""

    def __init__(self, period: float) -> None:
        self.id = f"v{next(_IDS)}"
        self.period = float(period)
        self.widget = w.Text(value="", layout=w.Layout(display="none"))
        self.widget.add_class(FEED_CLASS)
        self.poses: deque[StampedPose] = deque(maxlen=FEED_POSES)
        self.sent = 0
        self._sent_at = -float("inf")
        self._promised: float | None = HEARTBEAT_S  # None: no next message promised (not running)
        self._last: tuple[object, ...] | None = None
        self._placement: tuple[list[float], float, float, float] | None = None

    def clear(self) -> None:
        """A new source: the old chair's poses are not interpolated into the new one's."""
        self.poses.clear()
        self._last = None

    def remember(self, t: float, x: float, y: float, yaw: float, v: float) -> bool:
        """Add the chair's pose at kernel time ``t`` (a repeated stamp adds nothing); True if new."""
        if self.poses and t <= self.poses[-1].t:
            return False
        self.poses.append(StampedPose(float(t), float(x), float(y), float(yaw), float(v)))
        return True

    def drawn(self, view: Viewport, footprint_m: float) -> None:
        """The kernel drew a canvas frame with ``view``: the page places the chair by this view until
        the next frame (the view may follow the chair before the map under it is drawn again)."""
        self._placement = (
            [round(v, 4) for v in pixel_affine(view)],
            round(view.chair_radius_px(footprint_m), 2),
            round(view.dot_radius_px(footprint_m), 2),
            round(float(footprint_m), 3),
        )

    def payload(self, now: float, seq: int, stale: bool) -> dict[str, Any]:
        px, r, dot, m = self._placement or ([1.0, 0.0, -1.0, 0.0], 0.0, 0.0, 0.0)
        return {
            "id": self.id,
            "seq": int(seq),
            "now": round(now, 4),
            "next": self._promised,
            "behind": round(self.period, 4),
            "poses": [[round(v, 4) for v in (p.t, p.x, p.y, p.yaw, p.v)] for p in self.poses],
            "px": px,
            "r": r,
            "dot": dot,
            "m": m,
            "stale": bool(stale),
        }

    def send(self, now: float, seq: int, stale: bool, *, running: bool = True) -> bool:
        """Send when something the page draws changed, when the last message promised another one
        within a frame, or when the heartbeat is due; True if sent (nothing before the first frame).
        Not ``running`` (the map shown without the render loop, or the loop stopping) promises
        nothing: the page must not call a view that is not updating a slow link."""
        if self._placement is None:
            return False
        key = (self.poses[-1] if self.poses else None, self._placement, stale)
        changed = key != self._last
        promised = self._promised
        due = running and (promised is None or promised < HEARTBEAT_S or now - self._sent_at >= HEARTBEAT_S)
        if not changed and not due and not (promised is not None and not running):
            return False
        # while the chair moves, another message comes next tick; parked, within the heartbeat
        self._promised = None if not running else round(self.period, 4) if changed else HEARTBEAT_S
        self.widget.value = json.dumps(self.payload(now, seq, stale), separators=(",", ":"))
        self._last, self._sent_at = key, now
        self.sent += 1
        return True
