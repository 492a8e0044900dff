"""Stop every navigation goal this link runs, and every goal the chair runs that a cancel-all reaches.

Issue 38: a Stop that only sends zero velocity leaves a goal driving: Nav2's controller and move_base
keep publishing their own velocity. :func:`stop_goals` (``ChairLink.stop_goals``):

1. cancels each running goal this link started (:func:`track` keeps them, from
   :func:`pmk_nb.chair.link.goals.navigate.navigate`); each goal's watch verifies its cancel;
2. on a second websocket (:mod:`pmk_nb.chair.link.transport.side_channel`: rosbridge_suite holds the link's
   own messages behind its running goal), on a daemon thread:
   * publishes the Stop on :data:`pmk_nb.goalbeat.STOP_TOPIC`, for ``pmk robot goal-watchdog``, which
     cancels natively on the chair;
   * ROS 2: calls ``<action>/_action/cancel_goal`` of Nav2's two actions with a zero goal id and stamp
     (``action_msgs/srv/CancelGoal``: every goal of that action, whoever sent it);
   * ROS 1: an empty ``actionlib_msgs/GoalID`` on ``/move_base/cancel`` (actionlib: all goals);
   * zero velocity at 20 Hz for :data:`BURST_S`.
   When the second socket cannot be opened, zero velocity goes over the link's own connection.

The goal gate: ``link.goal_gate`` (None, or a callable returning the wall time of a latched Stop, else
None) is asked before every goal; a latched Stop refuses the goal with :class:`GoalsStopped`.
"""

from __future__ import annotations

import json
import logging
import threading
import time
import weakref
from typing import TYPE_CHECKING

from websockets.exceptions import WebSocketException

from pmk_nb.chair.link.goals.goal import GoalHandle, NavigationError
from pmk_nb.chair.link.goals.heartbeat import client_id
from pmk_nb.chair.link.transport.side_channel import SIDE_ERRORS, ZERO, side_connect
from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.goalbeat import STOP_REPEAT_HZ, STOP_REPEAT_S, STOP_TOPIC, stop_message
from pmk_nb.wire import CANCEL_GOAL_TYPE as CANCEL_SERVICE
from pmk_nb.wire import MOVE_BASE_CANCEL, NAV2_ACTION, NAV2_THROUGH, spell_type

if TYPE_CHECKING:
    from pmk_nb.chair.link.core import LinkCore

LOG = logging.getLogger(__name__)
#: zero velocity after the cancels: short, since a chair released after a Stop must not meet stale
#: zeros from it (the cancels stop the goals; the zeros stop what has no goal and what a held link sent)
BURST_HZ, BURST_S = 20.0, 0.25
_RUNNING: weakref.WeakKeyDictionary[LinkCore, set[GoalHandle]] = weakref.WeakKeyDictionary()
_LOCK = threading.Lock()
STOP_ERRORS: tuple[type[BaseException], ...] = (*SIDE_ERRORS, WebSocketException)


class GoalsStopped(NavigationError):
    """A goal refused because a Stop is latched for this chair (``stop_at``: its wall time); it is
    released on the page where it was pressed."""

    def __init__(self, message: str, *, stop_at: float, host: str | None = None, port: int | None = None) -> None:
        super().__init__(message, route="stop latch", host=host, port=port)
        self.stop_at = stop_at


def latched_at(link: LinkCore) -> float | None:
    """The wall time of the Stop latched for ``link``'s chair (``link.goal_gate``), else None."""
    gate = getattr(link, "goal_gate", None)
    return gate() if gate is not None else None


def check_gate(link: LinkCore) -> None:
    """Raise :class:`GoalsStopped` when ``link.goal_gate`` says a Stop is latched."""
    stop_at = latched_at(link)
    if stop_at is not None:
        raise GoalsStopped(
            f"Stopped (at {time.strftime('%H:%M', time.localtime(stop_at))}): no goal is sent to the chair at "
            f"{link.host}:{link.port} until the Stop is released on the page where it was pressed",
            stop_at=stop_at,
            host=link.host,
            port=link.port,
        )


def track(link: LinkCore, handle: GoalHandle) -> None:
    """Keep ``handle`` among ``link``'s running goals until it is done; cancel it at once when a Stop
    was latched while it was being sent (after the gate let it through: no goal slips past a Stop)."""
    with _LOCK:
        _RUNNING.setdefault(link, set()).add(handle)
    ref = weakref.ref(link)  # the handle's callback must not keep the link (the registry's weak key) alive

    def on_update(progress: object) -> None:  # roslibpy's I/O thread: store only
        owner = ref()
        if getattr(progress, "done", False) and owner is not None:
            with _LOCK:
                _RUNNING.get(owner, set()).discard(handle)

    handle.on_update(on_update)
    if handle.progress().done:
        on_update(handle.progress())
    elif latched_at(link) is not None:
        handle.cancel()


def running(link: LinkCore) -> list[GoalHandle]:
    """The goals ``link`` started that have not ended."""
    with _LOCK:
        return [h for h in _RUNNING.get(link, set()) if not h.progress().done]


def stop_goals(
    link: LinkCore, cmd_vel_topic: str | None = None, *, wait: bool = False, clock: Clock = MONOTONIC
) -> list[GoalHandle]:
    """Cancel every goal (see the module docstring); returns this link's goals that were cancelled.
    The native cancels and the zero burst go on a daemon thread (``wait``: block until sent), paced
    by ``clock`` (a ``VirtualClock`` in tests)."""
    handles = running(link)
    for handle in handles:
        handle.cancel()
    thread = threading.Thread(
        target=native_stop,
        args=(link, cmd_vel_topic or link.cmd_vel_topic, clock),
        daemon=True,
        name="pmk-stop-goals",
    )
    thread.start()
    if wait:
        thread.join(BURST_S + 5.0)
    return handles


def native_stop(link: LinkCore, cmd_vel_topic: str, clock: Clock = MONOTONIC) -> bool:
    """The second-socket part of :func:`stop_goals`; False when the socket failed (zero velocity then
    went over the link's own connection)."""
    version = link.ros_version
    try:
        with side_connect(link) as ws:
            for message in _stop_messages(version, cmd_vel_topic):
                ws.send(json.dumps(message))
            publish = json.dumps({"op": "publish", "topic": cmd_vel_topic, "msg": ZERO})
            stop = json.dumps({"op": "publish", "topic": STOP_TOPIC, "msg": {"data": stop_message(client_id())}})
            for _ in range(round(BURST_HZ * BURST_S)):
                ws.send(publish)
                ws.send(stop)
                clock.sleep(1.0 / BURST_HZ)
            ws.send(json.dumps({"op": "unadvertise", "topic": cmd_vel_topic}))
        threading.Thread(target=_repeat_stop, args=(link, stop, clock), daemon=True, name="pmk-stop-repeat").start()
    except STOP_ERRORS as err:
        LOG.warning(
            "stop over a second connection to %s:%s failed (%s): zero velocity on the link", link.host, link.port, err
        )
        for _ in range(round(BURST_HZ * BURST_S)):
            link.publish_cmd_vel(0.0, 0.0, cmd_vel_topic)
            clock.sleep(1.0 / BURST_HZ)
        return False
    return True


def _repeat_stop(link: LinkCore, stop: str, clock: Clock = MONOTONIC) -> None:
    """The Stop again for :data:`STOP_REPEAT_S` on a socket of its own: the publisher a bridge creates on
    an advertise meets the watchdog's subscription only after discovery (rosbridge-server-rs: a Stop
    sent on a socket that lives a quarter of a second never reached it), and the cancels and the zero
    burst above must not wait for that."""
    try:
        with side_connect(link) as ws:
            ws.send(
                json.dumps(
                    {"op": "advertise", "topic": STOP_TOPIC, "type": spell_type("std_msgs/String", link.ros_version)}
                )
            )
            for _ in range(round(STOP_REPEAT_S * STOP_REPEAT_HZ)):
                ws.send(stop)
                clock.sleep(1.0 / STOP_REPEAT_HZ)
    except STOP_ERRORS as err:
        LOG.warning("repeating the Stop to %s:%s failed (%s)", link.host, link.port, err)


def _stop_messages(version: int | None, cmd_vel_topic: str) -> list[dict[str, object]]:
    """The rosbridge ops of a Stop, for ROS ``version`` (None: unknown, both kinds of cancel)."""
    string = spell_type("std_msgs/String", version)
    out: list[dict[str, object]] = [
        {"op": "advertise", "topic": STOP_TOPIC, "type": string},
        {"op": "publish", "topic": STOP_TOPIC, "msg": {"data": stop_message(client_id())}},
    ]
    if version != 1:  # zero id and stamp: every goal of the action
        for n, (action, _type) in enumerate((NAV2_ACTION, NAV2_THROUGH)):
            service = f"{action}/_action/cancel_goal"
            out.append({"op": "call_service", "id": f"pmk-stop-{n}", "service": service, "type": CANCEL_SERVICE})
    if version != 2:  # actionlib: an empty GoalID cancels every goal
        cancel = MOVE_BASE_CANCEL
        out.append({"op": "advertise", "topic": cancel, "type": "actionlib_msgs/GoalID"})
        out.append({"op": "publish", "topic": cancel, "msg": {"stamp": {"secs": 0, "nsecs": 0}, "id": ""}})
    out.append({"op": "advertise", "topic": cmd_vel_topic, "type": spell_type("geometry_msgs/Twist", version)})
    return out
