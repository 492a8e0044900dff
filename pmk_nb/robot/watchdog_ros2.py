"""``pmk robot goal-watchdog``, ROS 2 (rclpy): cancel Nav2's goals when a dashboard's heartbeat stops.

Why: the official ROS 2 rosbridge keeps a client's action goals alive after its websocket drops, so
a tablet out of Wi-Fi range leaves the chair driving to its goal with nobody watching (issue 24).
This node runs on the chair beside Nav2 and listens to ``/pmk/goal_heartbeat``
(:mod:`pmk_nb.goalbeat`); when an armed dashboard is silent for ``--silence`` s it calls each
action's ``<action>/_action/cancel_goal`` service with a zero goal id and a zero stamp, which
``action_msgs/srv/CancelGoal`` defines as "cancel all goals" of that action server.

It also listens to the dashboard's Stop on ``/pmk/stop`` (:data:`pmk_nb.goalbeat.STOP_TOPIC`, issue
38) and cancels all goals the same way at once: a bridge may hold the dashboard's own cancel behind
the goal it cancels, and a goal another page started is this page's only through a cancel-all.

Single-threaded: the subscription, the 10 Hz timer and the service replies all run in rclpy's
executor, so :class:`~pmk_nb.robot.goalwatch.GoalWatch` needs no lock.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from pmk_nb.goalbeat import SILENCE_S, STOP_TOPIC, TOPIC, Beat, stop_client
from pmk_nb.robot.goalwatch import READY_LINE, GoalWatch, StopDebounce, Trip
from pmk_nb.wire import (
    CANCEL_ERROR_GOAL_TERMINATED,
    CANCEL_ERROR_NONE,
    CANCEL_ERROR_REJECTED,
    CANCEL_ERROR_UNKNOWN_GOAL_ID,
    NAV2_ACTIONS,
)

ACTIONS = NAV2_ACTIONS
TICK_S = 0.1
# action_msgs/srv/CancelGoal return codes
CANCEL_CODES = {
    CANCEL_ERROR_NONE: "accepted",
    CANCEL_ERROR_REJECTED: "rejected",
    CANCEL_ERROR_UNKNOWN_GOAL_ID: "unknown goal id",
    CANCEL_ERROR_GOAL_TERMINATED: "goal already terminated",
}


class Ros2Watchdog:
    """The node's parts: one cancel client per action, the heartbeat subscription, the timer."""

    def __init__(
        self,
        node: Any,
        watch: GoalWatch,
        actions: Sequence[str] = ACTIONS,
        topic: str = TOPIC,
        stop_topic: str = STOP_TOPIC,
    ) -> None:
        from action_msgs.srv import CancelGoal
        from rclpy.qos import QoSProfile, ReliabilityPolicy
        from std_msgs.msg import String

        self.node, self.watch, self.log = node, watch, node.get_logger()
        self.cancel_type = CancelGoal
        self.clients = {name: node.create_client(CancelGoal, f"{name}/_action/cancel_goal") for name in actions}
        # best effort matches any publisher's reliability (a bridge may publish either way)
        qos = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)
        self.subscription = node.create_subscription(String, topic, self.on_beat, qos)
        self.stop_subscription = node.create_subscription(String, stop_topic, self.on_stop, qos)
        self.timer = node.create_timer(TICK_S, self.on_tick)
        self.cancels_sent = 0
        self.stops = StopDebounce()

    def on_beat(self, msg: Any) -> None:
        beat = Beat.decode(msg.data)
        if beat is None:
            self.log.warning(f"not a goal heartbeat, ignored: {msg.data[:80]!r}")
            return
        change = self.watch.beat(beat)
        if change is not None:
            what = "armed: a goal runs" if change.armed else "disarmed: its goals ended"
            self.log.info(f"{change.client}: {what}")

    def on_stop(self, msg: Any) -> None:
        """The dashboard's Stop: every goal ends now (any message counts: a Stop errs on stopping). The
        dashboard repeats a Stop for a while: each repeat cancels again, only a new press is logged."""
        client = stop_client(msg.data)
        self.cancel_all(f"{client}: Stop pressed", quiet=not self.stops.admit(client))

    def on_tick(self) -> None:
        for trip in self.watch.tick():
            self.cancel_all(silent_text(trip))

    def cancel_all(self, why: str, *, quiet: bool = False) -> None:
        """Cancel every goal of every watched action (zero id + zero stamp = all goals); ``quiet``: a repeat
        of the last Stop, sent but not logged."""
        if not quiet:
            self.log.warning(f"{why}: cancelling all goals of {', '.join(self.clients)}")
        for name, client in self.clients.items():
            if not client.service_is_ready():
                if not quiet:
                    self.log.info(f"{name}: no action server offers cancel_goal here; nothing to cancel")
                continue
            future = client.call_async(self.cancel_type.Request())  # all fields zero: cancel all
            future.add_done_callback(lambda f, name=name, quiet=quiet: self._cancelled(name, f, quiet))
            self.cancels_sent += 1

    def _cancelled(self, name: str, future: Any, quiet: bool = False) -> None:
        reply = future.result()
        if reply is None:
            self.log.error(f"{name}: the cancel request failed: {future.exception()}")
            return
        if quiet:
            return
        code = CANCEL_CODES.get(reply.return_code, str(reply.return_code))
        self.log.warning(f"{name}: cancel {code}; {len(reply.goals_canceling)} goal(s) cancelling")


def silent_text(trip: Trip) -> str:
    return f"{trip.client}: heartbeat silent for {trip.silent_s:.1f} s with {trip.goals} goal(s) running"


def run(silence_s: float = SILENCE_S, actions: Sequence[str] = ACTIONS, topic: str = TOPIC) -> int:
    """Spin until interrupted; prints READY_LINE once subscribed."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    rclpy.init()
    node = rclpy.create_node("pmk_goal_watchdog")
    Ros2Watchdog(node, GoalWatch(silence_s), actions, topic)
    node.get_logger().info(
        f"watching {topic}: cancel {', '.join(actions)} after {silence_s:g} s of silence, and at once on {STOP_TOPIC}"
    )
    print(READY_LINE, flush=True)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0
