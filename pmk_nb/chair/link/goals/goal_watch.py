"""The goal watch: one small daemon thread per goal that turns silence into true states.

Every :data:`TICK` it checks, in this order:

* the link: dropped -> ``link_lost`` ("the chair may still be driving": rosbridge_suite does not
  cancel a lost client's goals). Back -> re-attach: the action's status topic (Nav2, via
  :class:`~pmk_nb.chair.link.goals.goal_attach.ActionStatusFollower`), actionlib's status (roslibpy
  re-subscribes, so its events resume) or, failing both within :data:`REATTACH_S`, the pose. With
  the setting ``on_link_loss="cancel"`` the goal is cancelled once the link is back;
* acceptance: nothing accepted the goal within ``accept_s`` -> ``no_answer`` and a cancel;
* silence: no result or feedback for ``quiet_s`` -> ``progress().quiet_s`` is set;
* a cancel: odometry must show the chair stopped within ``verify_s``; if not -> ``cancel_ignored``,
  the cancel again and zero velocity at :data:`BURST_HZ` for :data:`BURST_S` s over a second
  connection (:mod:`pmk_nb.chair.link.transport.side_channel`), from this thread (never roslibpy's I/O thread).
  Judged only after ``verify_s`` (a chair yet to start looks stopped); a goal still unanswered then,
  or no odometry at all, gets the same burst before anything is called honoured.

Hooks (``on_end``) run when the watch ends, for things that live as long as the goal.

Time is the goal's clock (``GoalHandle.clock``): its ticks, deadlines and bursts; the link's stamps
(``Odometry.received``, ``Pose2D.received``) are read on the same clock (a fake link's in tests).
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

from pmk_nb.chair.link.goals import goal_words as words
from pmk_nb.chair.link.goals.goal import ARRIVE_TOLERANCE, GoalHandle, GoalPolicy, GoalStatus
from pmk_nb.chair.link.transport.side_channel import side_stop
from pmk_nb.wire import (
    STATUS_ABORTED,
    STATUS_ACCEPTED,
    STATUS_CANCELED,
    STATUS_CANCELING,
    STATUS_EXECUTING,
    STATUS_SUCCEEDED,
)

if TYPE_CHECKING:
    from pmk_nb.chair.link.core import LinkCore

LOG = logging.getLogger(__name__)
TICK = 0.05
REATTACH_S = 2.0  # after a reconnect: how long to wait for the chair's word before reading the pose
BURST_HZ, BURST_S = 20.0, 1.0
STOPPED_V, STOPPED_W = 0.03, 0.05  # m/s, rad/s: odometry this still counts as stopped
STILL_HOLD_S = 0.5  # s: a cancel is honoured only after this long without motion (capped at verify_s)
LINGER_S = 3.0  # keep watching a finished goal this long while a cancel is being verified
# action_msgs/GoalStatus (the action's status topic) -> ours
STATUS_CODES = {
    STATUS_ACCEPTED: GoalStatus.MOVING,
    STATUS_EXECUTING: GoalStatus.MOVING,
    STATUS_CANCELING: GoalStatus.MOVING,
    STATUS_SUCCEEDED: GoalStatus.ARRIVED,
    STATUS_CANCELED: GoalStatus.CANCELLED,
    STATUS_ABORTED: GoalStatus.ABORTED,
}


class GoalWatch:
    """Watches one goal (see the module docstring); ``start()`` once."""

    def __init__(self, link: LinkCore, handle: GoalHandle, kind: str, policy: GoalPolicy) -> None:
        self.link, self.handle, self.kind, self.policy = link, handle, kind, policy
        self.clock = handle.clock
        self._stoppers: list[Callable[[], None]] = []
        self.lost = False
        self.was_lost = False
        self.back_at: float | None = None
        self._applied_code: int | None = None
        self._verifying: float | None = None  # the cancel being verified (its time)
        self._seen_cancel: float | None = None
        self._moved_at: float | None = None  # the last fresh odometry showing motion since the cancel
        self._blind_burst = False  # the cancel sent again with no odometry to judge it by
        self._thread = threading.Thread(target=self._run, daemon=True, name="pmk-goal-watch")

    def on_end(self, stop: Callable[[], None]) -> None:
        self._stoppers.append(stop)

    def start(self) -> None:
        self._thread.start()

    def _run(self) -> None:
        ended: float | None = None
        try:
            while True:
                now = self.clock.now()
                self.tick(now)
                if self.link.ros is None:  # the link was closed (not reconnecting): nothing more to learn
                    return
                if self.handle.progress().done:
                    ended = ended or now
                    if self._verifying is None or now - ended > LINGER_S:
                        return
                self.clock.sleep(TICK)
        except Exception:  # a bug must not leave the goal unwatched silently
            LOG.exception("goal watch failed")
        finally:
            follower = self.handle.follower
            if follower is not None:
                follower.close()
            for stop in self._stoppers:
                try:
                    stop()
                except Exception:
                    LOG.exception("goal watch hook failed")

    def tick(self, now: float) -> None:
        h, p = self.handle, self.handle.progress()
        if not p.done and not self._link(now, p.goal[:2]):
            return
        if p.status is GoalStatus.PENDING and now - h.sent_at > self.policy.accept_s:
            h.update(GoalStatus.NO_ANSWER, text=words.no_answer(self.policy.accept_s), news=False)
            h.cancel()
        quiet = now - h.last_news
        if not p.done and quiet > self.policy.quiet_s and (p.quiet_s is None or quiet - p.quiet_s >= 1.0):
            h.mark_quiet(quiet)
        self._verify_cancel(now)

    # -- link loss and re-attach ---------------------------------------------------------------------
    def _link(self, now: float, goal: tuple[float, float]) -> bool:
        """False while the link is down; re-attaches when it is back."""
        h = self.handle
        if not self.link.is_connected:
            if not self.lost:
                self.lost = self.was_lost = True
                h.update(GoalStatus.LINK_LOST, text=words.link_lost(goal), news=False)
            return False
        if self.lost:
            self.lost, self.back_at = False, now
            h.update(text=words.link_back_asking(), news=False)
            if self.policy.on_link_loss == "cancel":
                h.cancel()
                h.update(text=words.link_back_cancelling(), news=False)
        if self.was_lost:
            self._reattach(now, goal)
        return True

    def _reattach(self, now: float, goal: tuple[float, float]) -> None:
        h, follower = self.handle, self.handle.follower
        if follower is not None and follower.uuid is not None and follower.heard_at > (self.back_at or 0.0):
            code = follower.code if follower.listed else None
            if code is not None and code != self._applied_code:
                self._applied_code = code
                status = STATUS_CODES.get(code, GoalStatus.MOVING)
                done = status in (GoalStatus.ARRIVED, GoalStatus.CANCELLED, GoalStatus.ABORTED)
                text = words.link_back_outcome(status.value) if done else words.link_back_still_driving()
                h.update(status, 0.0 if status is GoalStatus.ARRIVED else None, text)
                return
        if h.progress().status is not GoalStatus.LINK_LOST or self.kind == "topic":
            return  # the chair spoke after the reconnect (or the goal topic's poller follows the pose)
        if self.back_at is not None and now - self.back_at > REATTACH_S:
            pose = self.link.latest_pose()
            fresh = pose is not None and pose.received > self.back_at
            here = (pose.x, pose.y) if fresh and pose is not None else None
            if here is not None and math.dist(here, goal) <= ARRIVE_TOLERANCE:
                h.update(GoalStatus.ARRIVED, math.dist(here, goal), words.link_back_at_goal(), news=False)
            elif here is not None or now - self.back_at > 3 * REATTACH_S:
                h.update(GoalStatus.UNKNOWN, text=words.link_back_unknown(here), news=False)
            else:
                self.link.start_streams()  # the pose tells where the chair is

    # -- verified cancel -----------------------------------------------------------------------------
    def _verify_cancel(self, now: float) -> None:
        """Judge a cancel by odometry once ``verify_s`` has passed: moving then -> ``cancel_ignored``;
        still, with no motion in the last :data:`STILL_HOLD_S` -> honoured. Not earlier: a chair
        that has not yet started (a goal just accepted) is still at first and drives on when the
        bridge holds the cancel (rosbridge_suite); the first still sample proves nothing."""
        h = self.handle
        if h.cancel_at is not None and h.cancel_at != self._seen_cancel:
            self._seen_cancel = self._verifying = h.cancel_at
            self._moved_at, self._blind_burst = None, False
            self.link.start_streams()  # odometry tells whether the chair stops
            if h.progress().status is GoalStatus.CANCEL_IGNORED:
                self.zero_burst()  # Stop pressed again: the chair is known to ignore the cancel
        since = self._verifying
        if since is None or h.cancel_honoured is not None:
            return
        odom = self.link.latest_odom()
        fresh = odom is not None and odom.received > since
        moving = fresh and odom is not None and (abs(odom.v) >= STOPPED_V or abs(odom.w) >= STOPPED_W)
        if moving and odom is not None:
            self._moved_at = odom.received
        if now - since <= self.policy.verify_s:
            return
        if not fresh:
            if not self._blind_burst:  # cannot tell: the cancel again where rosbridge_suite does not hold it
                self._blind_burst = True
                self.zero_burst()
            return  # keep waiting (the panel says "cancel sent")
        if not moving and not h.progress().done and not self._blind_burst:
            # still, but the goal runs on unanswered: a held cancel and a chair yet to start look
            # the same, so the cancel goes again where rosbridge_suite does not hold it
            self._blind_burst = True
            self.zero_burst()
        if not moving and (self._moved_at is None or now - self._moved_at >= min(STILL_HOLD_S, self.policy.verify_s)):
            h.cancel_honoured, self._verifying = True, None
        elif moving:
            h.cancel_honoured = False
            h.update(GoalStatus.CANCEL_IGNORED, text=words.cancel_ignored(self.policy.verify_s), news=False)
            self._verifying = None
            self.zero_burst()

    def zero_burst(self) -> None:
        """Zero velocity at BURST_HZ for BURST_S s, with the cancel again, over a second connection
        (rosbridge_suite holds the link's own behind the goal: see side_channel); over the link's
        own connection when that fails. On this thread, never roslibpy's."""
        self.handle.zero_bursts += 1
        link, topic = self.link, self.link.cmd_vel_topic
        if side_stop(link, topic, self.handle.cancel_ref, hz=BURST_HZ, seconds=BURST_S, clock=self.clock):
            return
        for _ in range(round(BURST_HZ * BURST_S)):
            link.publish_cmd_vel(0.0, 0.0)
            self.clock.sleep(1.0 / BURST_HZ)
