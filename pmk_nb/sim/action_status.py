"""``<action>/_action/status`` of the simulator's Nav2 action servers, as rclcpp's action server
publishes it: an ``action_msgs/msg/GoalStatusArray`` on every change, kept by late subscribers
(the topic's QoS is transient local), finished goals listed a while longer (rclcpp keeps a result
for ``result_timeout``, 15 min by default; :data:`KEEP_DONE_S` here).

A client that lost its websocket reads its goal's fate here after reconnecting: the bridge cannot
deliver the ``action_result`` to a socket that closed (see :mod:`pmk_nb.sim.bridge_modes`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from pmk_nb.clock import MONOTONIC, WALL, Clock
from pmk_nb.sim.session import resolve_name

if TYPE_CHECKING:
    from pmk_nb.sim.actions import GoalRef
    from pmk_nb.sim.messages import Names
    from pmk_nb.sim.protocol import Bridge

KEEP_DONE_S = 120.0
TERMINAL = (4, 5, 6)  # action_msgs/GoalStatus succeeded, canceled, aborted


class ActionStatus:
    """The status topics of the actions a bridge serves; ``set(ref, code)`` on each change. ``clock``
    keeps finished goals :data:`KEEP_DONE_S`; ``wall`` stamps a goal first seen here."""

    def __init__(
        self, bridge: Bridge, names: Names, actions: tuple[str, ...], *, clock: Clock = MONOTONIC, wall: Clock = WALL
    ) -> None:
        self.bridge, self.names = bridge, names
        self.clock, self.wall = clock, wall
        self._goals: dict[str, dict[tuple[int, ...], tuple[int, float, float]]] = {a: {} for a in actions}
        for action in actions:
            bridge.advertise_internal(
                f"{action}/_action/status", names.msg("action_msgs", "GoalStatusArray"), latched=True
            )

    def set(self, ref: GoalRef, code: int) -> None:
        action = resolve_name(ref.action)
        goals = self._goals.get(action)
        if goals is None:
            return
        now = self.clock.now()
        accepted = goals.get(ref.uuid, (0, self.wall.now(), 0.0))[1]
        goals[ref.uuid] = (code, accepted, now if code in TERMINAL else 0.0)
        for key, (c, _, done) in list(goals.items()):
            if c in TERMINAL and now - done > KEEP_DONE_S:
                del goals[key]
        self.bridge.publish(f"{action}/_action/status", {"status_list": [self._entry(k, v) for k, v in goals.items()]})

    def _entry(self, key: tuple[int, ...], value: tuple[int, float, float]) -> dict[str, Any]:
        info = {"goal_id": {"uuid": list(key)}, "stamp": self.names.stamp(value[1])}
        return {"goal_info": info, "status": value[0]}
