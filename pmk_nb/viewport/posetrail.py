"""Where the chair was at a message's header stamp: a short odometry trail, interpolated (issue 40).

A scan is cast at the instant its header stamp names; by the time it is drawn the chair has moved
on (a turning chair at 40 deg/s turns 4 deg in 0.1 s: half a metre at 8 m).  Drawing the rays from
the newest pose makes them cut through walls; drawing them from the pose the chair had at the stamp
keeps the hits on the walls.  The trail keeps odometry poses by stamp (the chair's clock, so the
link's arrival times play no part) and answers the motion between a stamp and the newest sample;
the live view applies that motion to the pose it draws (which may be in ``map``).  Pure maths.
"""

from __future__ import annotations

import bisect
import math
from collections import deque

from pmk_nb.viewport.pose import Transform2D
from pmk_nb.wire import wrap_angle

#: Samples kept: 64 at 20-50 Hz odometry is one to three seconds, far more than any scan's age.
TRAIL_SIZE = 64
#: A stamp this far (s) past the newest sample is still taken as the newest (clocks are not exact).
LATE_SLACK_S = 0.05

Pose = tuple[float, float, float]


class PoseTrail:
    """Odometry poses by header stamp (seconds), oldest first; bounded."""

    def __init__(self, size: int = TRAIL_SIZE) -> None:
        self._stamps: deque[float] = deque(maxlen=size)
        self._poses: deque[Pose] = deque(maxlen=size)

    def __len__(self) -> int:
        return len(self._stamps)

    def clear(self) -> None:
        self._stamps.clear()
        self._poses.clear()

    def add(self, stamp: float | None, pose: Pose) -> None:
        """Remember ``pose`` at ``stamp``; a repeated stamp is ignored, an older one (the chair's clock
        jumped back: a restarted simulation, a bag looped) starts the trail again."""
        if stamp is None or not math.isfinite(stamp) or not all(math.isfinite(v) for v in pose):
            return
        if self._stamps and stamp <= self._stamps[-1]:
            if stamp == self._stamps[-1]:
                return
            self.clear()
        self._stamps.append(float(stamp))
        self._poses.append((float(pose[0]), float(pose[1]), float(pose[2])))

    @property
    def newest(self) -> tuple[float, Pose] | None:
        """(stamp, pose) of the newest sample."""
        return (self._stamps[-1], self._poses[-1]) if self._stamps else None

    def at(self, stamp: float | None) -> Pose | None:
        """The pose at ``stamp``, linear between the two samples around it (yaw the short way round);
        None when the stamp is older than the trail or newer than its newest sample by more than
        :data:`LATE_SLACK_S` (the caller then has nothing better than the newest pose)."""
        if stamp is None or not math.isfinite(stamp) or not self._stamps:
            return None
        stamps = list(self._stamps)
        if stamp >= stamps[-1]:
            return self._poses[-1] if stamp - stamps[-1] <= LATE_SLACK_S else None
        if stamp < stamps[0]:
            return None
        i = bisect.bisect_right(stamps, stamp)  # stamps[i-1] <= stamp < stamps[i]
        t0, t1 = stamps[i - 1], stamps[i]
        (x0, y0, a0), (x1, y1, a1) = self._poses[i - 1], self._poses[i]
        f = (stamp - t0) / (t1 - t0)
        return (x0 + f * (x1 - x0), y0 + f * (y1 - y0), wrap_angle(a0 + f * wrap_angle(a1 - a0)))

    def since(self, stamp: float | None) -> Transform2D | None:
        """The chair's motion from ``stamp`` to the newest sample, in the chair's frame at ``stamp``
        (``then^-1 * newest``), or None when the trail cannot tell (see :meth:`at`)."""
        then = self.at(stamp)
        if then is None or not self._poses:
            return None
        return Transform2D(*then).inverse().compose(Transform2D(*self._poses[-1]))


def pose_at_stamp(now: Pose, trail: PoseTrail, stamp: float | None) -> Pose | None:
    """Where a chair now at ``now`` (any fixed frame: map or odom, at the trail's newest sample) was at
    ``stamp``: ``now * moved^-1`` with ``moved`` the odometry motion since; None when the trail
    cannot tell."""
    moved = trail.since(stamp)
    if moved is None:
        return None
    then = Transform2D(*now).compose(moved.inverse())
    return then.x, then.y, then.theta
