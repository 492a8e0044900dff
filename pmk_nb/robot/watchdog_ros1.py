"""``pmk robot goal-watchdog --ros1`` (rospy): cancel move_base's goals when a dashboard's heartbeat stops.

The ROS 1 rosbridge has no action ops: the dashboard drives move_base over actionlib topics, and
when its socket drops nobody cancels. This node listens to ``/pmk/goal_heartbeat``
(:mod:`pmk_nb.goalbeat`) and, when an armed dashboard is silent for ``--silence`` s, publishes an
empty ``actionlib_msgs/GoalID`` on ``/move_base/cancel``: a zero id and a zero stamp is actionlib's
"cancel all goals". The dashboard's Stop on ``/pmk/stop`` (:data:`pmk_nb.goalbeat.STOP_TOPIC`, issue
38) publishes the same at once.

Runs with the system Python that has Debian's python3-rospy (as :mod:`pmk_nb.robot.ros1_mapserver`);
imports only the standard library, rospy, Debian's message packages and the pure goal watch.
rospy calls the subscriber and the timer on threads of its own: a lock keeps the watch consistent.
Run: ``PYTHONPATH=<checkout> /usr/bin/python3 -m pmk_nb.robot.watchdog_ros1 [--silence S]``.
"""

from __future__ import annotations

import argparse
import threading
from typing import Any

from pmk_nb.goalbeat import SILENCE_S, STOP_TOPIC, TOPIC, Beat, stop_client
from pmk_nb.robot.goalwatch import READY_LINE, GoalWatch, StopDebounce
from pmk_nb.wire import MOVE_BASE_CANCEL

CANCEL_TOPIC = MOVE_BASE_CANCEL
TICK_S = 0.1


class Ros1Watchdog:
    """The heartbeat subscriber, the cancel publisher and the timer of one rospy node."""

    def __init__(
        self, watch: GoalWatch, topic: str = TOPIC, cancel_topic: str = CANCEL_TOPIC, stop_topic: str = STOP_TOPIC
    ) -> None:
        import rospy
        from actionlib_msgs.msg import GoalID
        from std_msgs.msg import String

        self.rospy, self.watch, self.cancel_topic = rospy, watch, cancel_topic
        self.goal_id = GoalID
        self.lock = threading.Lock()
        self.cancel_pub = rospy.Publisher(cancel_topic, GoalID, queue_size=10)
        self.subscriber = rospy.Subscriber(topic, String, self.on_beat, queue_size=10)
        self.stop_subscriber = rospy.Subscriber(stop_topic, String, self.on_stop, queue_size=10)
        self.timer = rospy.Timer(rospy.Duration(TICK_S), self.on_tick)
        self.cancels_sent = 0
        self.stops = StopDebounce()

    def on_beat(self, msg: Any) -> None:
        beat = Beat.decode(msg.data)
        if beat is None:
            self.rospy.logwarn(f"not a goal heartbeat, ignored: {msg.data[:80]!r}")
            return
        with self.lock:
            change = self.watch.beat(beat)
        if change is not None:
            what = "armed: a goal runs" if change.armed else "disarmed: its goals ended"
            self.rospy.loginfo(f"{change.client}: {what}")

    def on_stop(self, msg: Any) -> None:
        """The dashboard's Stop: cancel all goals now (any message counts: a Stop errs on stopping)."""
        self.cancel_pub.publish(self.goal_id())
        with self.lock:
            self.cancels_sent += 1
            new = self.stops.admit(stop_client(msg.data))
        if new:  # the dashboard repeats a Stop for a while: each repeat cancels again, one line per press
            self.rospy.logwarn(
                f"{stop_client(msg.data)}: Stop pressed: "
                f"published an empty GoalID on {self.cancel_topic} (cancel all goals)"
            )

    def on_tick(self, _event: Any) -> None:
        with self.lock:
            trips = self.watch.tick()
        for trip in trips:
            self.cancel_pub.publish(self.goal_id())  # zero id, zero stamp: cancel all goals
            self.cancels_sent += 1
            self.rospy.logwarn(
                f"{trip.client}: heartbeat silent for {trip.silent_s:.1f} s with {trip.goals} goal(s) running: "
                f"published an empty GoalID on {self.cancel_topic} (cancel all goals)"
            )


def run(silence_s: float = SILENCE_S, topic: str = TOPIC, cancel_topic: str = CANCEL_TOPIC) -> int:
    """Start the node (ROS_MASTER_URI from the environment) and spin; prints READY_LINE once subscribed."""
    import rospy

    rospy.init_node("pmk_goal_watchdog", disable_signals=False)
    Ros1Watchdog(GoalWatch(silence_s), topic, cancel_topic)
    rospy.loginfo(
        f"watching {topic}: empty GoalID on {cancel_topic} after {silence_s:g} s of silence, "
        f"and at once on {STOP_TOPIC}"
    )
    print(READY_LINE, flush=True)
    rospy.spin()
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="pmk robot goal-watchdog --ros1", description=__doc__.splitlines()[0])
    ap.add_argument("--silence", type=float, default=SILENCE_S)
    ap.add_argument("--topic", default=TOPIC)
    ap.add_argument("--cancel-topic", default=CANCEL_TOPIC)
    args = ap.parse_args(argv)
    return run(args.silence, args.topic, args.cancel_topic)


if __name__ == "__main__":
    raise SystemExit(main())
