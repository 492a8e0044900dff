"""Where the page draws the chair between the kernel's updates (issue 41): pure maths.

The kernel sends the chair's recent poses, each stamped with the kernel's clock, a few dozen times a
second; the page draws at its display's rate (60 Hz) by interpolating between them.  It renders a
little behind (one update interval), so a new pose is normally already there when the drawing
reaches it; when an update is late it may carry the last motion on, but never more than one update
interval past the newest pose (a chair's position is not guessed further), and then holds.  When the
next update is overdue the page says "link slow" rather than freezing silently or jumping.

The page script (:mod:`pmk_nb.ui.live.page_script`) mirrors these functions line for line; the
tests here pin the rules both follow.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

from pmk_nb.viewport.view import Viewport
from pmk_nb.wire import wrap_angle

#: An update counts as late this long after the kernel's promise of the next one ran out (s).
LATE_GRACE_S = 0.25
#: A parked chair's feed: the kernel sends its pose again at least this often (s), so the page can
#: tell a still chair from a dead link.
HEARTBEAT_S = 0.5
#: Arrival offsets the page keeps to map the kernel's clock onto its own (the smallest wins).
OFFSET_WINDOW = 64
#: Poses the feed carries in each message (the page merges them by stamp).
FEED_POSES = 4


@dataclass(frozen=True)
class StampedPose:
    """The chair at kernel time ``t`` (s): position (m), yaw (rad), forward speed (m/s)."""

    t: float
    x: float
    y: float
    yaw: float
    v: float = 0.0


def pose_at(samples: Sequence[StampedPose], t: float) -> StampedPose | None:
    """The chair at kernel time ``t``: linear between the samples around it (yaw the short way).

    Before the first sample: the first.  After the newest: its motion since the one before carried
    on for at most one update interval (newest.t - previous.t), then held: never further ahead.
    ``samples`` are oldest first with increasing ``t``.
    """
    if not samples:
        return None
    first, last = samples[0], samples[-1]
    if t <= first.t or len(samples) == 1:
        return first if t <= first.t else last
    if t >= last.t:
        prev = samples[-2]
        step = last.t - prev.t
        ahead = min(t - last.t, step)
        return _between(prev, last, 1.0 + ahead / step, last.t + ahead) if step > 0 else last
    lo = 0
    hi = len(samples) - 1
    while hi - lo > 1:  # bisect on t
        mid = (lo + hi) // 2
        if samples[mid].t <= t:
            lo = mid
        else:
            hi = mid
    a, b = samples[lo], samples[hi]
    span = b.t - a.t
    return _between(a, b, (t - a.t) / span if span > 0 else 1.0, t)


def _between(a: StampedPose, b: StampedPose, f: float, t: float) -> StampedPose:
    """``a`` moved a fraction ``f`` of the way to ``b`` (``f`` up to 2: one step past ``b``)."""
    yaw = wrap_angle(a.yaw + f * wrap_angle(b.yaw - a.yaw))
    return StampedPose(t, a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), yaw, b.v)


def merge(samples: Sequence[StampedPose], new: Sequence[StampedPose], keep: int = 8) -> list[StampedPose]:
    """``samples`` and ``new`` by stamp, one per stamp (the newer message's wins), the last ``keep``.
    A stamp older than every kept one after a restart of the kernel's clock starts over."""
    by_t = {s.t: s for s in samples}
    if new and samples and new[-1].t < samples[0].t:
        by_t = {}
    for s in new:
        if all(math.isfinite(v) for v in (s.t, s.x, s.y, s.yaw, s.v)):
            by_t[s.t] = s
    return [by_t[t] for t in sorted(by_t)][-keep:]


class ClockOffset:
    """The page's clock minus the kernel's, from each update's (arrival, kernel send time): the
    smallest difference over a window is the one with the least transit delay in it."""

    def __init__(self, window: int = OFFSET_WINDOW) -> None:
        self._seen: deque[float] = deque(maxlen=window)

    def add(self, arrived: float, sent: float) -> float:
        self._seen.append(arrived - sent)
        return self.offset

    @property
    def offset(self) -> float:
        return min(self._seen) if self._seen else 0.0


def render_time(page_now: float, offset: float, behind: float) -> float:
    """The kernel time the page draws at ``page_now``: ``behind`` seconds back from the kernel's now."""
    return page_now - offset - max(behind, 0.0)


def late(page_now: float, arrived: float, next_within: float | None, grace: float = LATE_GRACE_S) -> bool:
    """Whether the update the kernel promised (``next_within`` s after the last, which arrived at
    ``arrived``) is overdue: the page then says "link slow".  None: no update was promised (the view
    is not running), so none is late."""
    return next_within is not None and page_now - arrived > max(next_within, 0.0) + grace


def pixel_affine(view: Viewport) -> tuple[float, float, float, float]:
    """(ax, bx, ay, by) with px = ax * x + bx, py = ay * y + by: the view's world -> canvas pixel map
    (no rotation: the map is drawn north up), for the page to place the chair with."""
    px, py = view.world_to_pixel([0.0, 1.0], [0.0, 1.0])
    ax, ay = float(px[1] - px[0]), float(py[1] - py[0])
    return ax, float(px[0]), ay, float(py[0])
