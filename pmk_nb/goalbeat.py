"""The goal heartbeat's wire format, spoken by the dashboard's link and the chair's goal watchdog.

Why: some rosbridge servers keep a client's navigation goals alive after its websocket drops (the
official ROS 2 bridge does, issue 24), so a tablet that leaves Wi-Fi range leaves the chair driving
with nobody watching. While a goal runs the link publishes a heartbeat; ``pmk robot goal-watchdog``
on the chair cancels navigation goals when it falls silent. An explicit "idle" beat ends a goal, so
that the watchdog disarms instead of cancelling a goal that finished.

A beat is a ``std_msgs/String`` whose ``data`` is a small JSON object (readable with
``ros2 topic echo``): ``{"client": ..., "active": true|false, "goals": n, "seq": n}``. Pure and
ROS-free: the ROS 1 watchdog imports it under the system Python.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

TOPIC = "/pmk/goal_heartbeat"
TYPE = "std_msgs/String"  # ROS 2 spelling: std_msgs/msg/String (the link spells it per version)
RATE_HZ = 2.0
SILENCE_S = 3.0  # the watchdog's default: 6 beats missed


@dataclass(frozen=True)
class Beat:
    """One heartbeat: who sends it, whether a goal of theirs runs, how many, a counter."""

    client: str
    active: bool
    goals: int = 0
    seq: int = 0

    def encode(self) -> str:
        return json.dumps({"client": self.client, "active": self.active, "goals": self.goals, "seq": self.seq})

    @classmethod
    def decode(cls, text: str) -> Beat | None:
        """The beat in ``text``; None for anything that is not one (a stray publisher on the topic)."""
        try:
            data = json.loads(text)
        except (TypeError, ValueError):
            return None
        if not isinstance(data, dict) or not isinstance(data.get("client"), str) or not data["client"]:
            return None
        active, goals, seq = data.get("active"), data.get("goals", 0), data.get("seq", 0)
        if not isinstance(active, bool) or not isinstance(goals, int) or not isinstance(seq, int):
            return None
        return cls(data["client"], active, goals, seq)


#: The dashboard's Stop, for ``pmk robot goal-watchdog`` (issue 38): a ``std_msgs/String`` whose
#: ``data`` is ``{"client": ..., "stop": true}``. Any message here means "cancel every navigation
#: goal now": the watchdog cancels them natively (Nav2's CancelGoal with a zero id, move_base's empty
#: GoalID), because a bridge may hold a client's own cancel behind the goal it cancels.
STOP_TOPIC = "/pmk/stop"
#: A dashboard repeats its Stop for this long at this rate on a socket of its own (a bridge's new
#: publisher meets the watchdog's subscription only after discovery); the watchdog takes the repeats
#: of one dashboard within that window as one press
STOP_REPEAT_S, STOP_REPEAT_HZ = 3.0, 10.0


def stop_message(client: str) -> str:
    """The ``data`` of one Stop on :data:`STOP_TOPIC`."""
    return json.dumps({"client": client, "stop": True})


def stop_client(text: str) -> str:
    """Who sent a Stop (for the log); "?" when the message is not ours: it still stops."""
    try:
        data = json.loads(text)
    except (TypeError, ValueError):
        return "?"
    client = data.get("client") if isinstance(data, dict) else None
    return client if isinstance(client, str) and client else "?"
