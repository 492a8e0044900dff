"""rosbridge ROS 2 action ops: ``send_action_goal`` and ``cancel_action_goal`` in, ``action_feedback``
and ``action_result`` out (rosbridge 2.0's ROSBRIDGE_PROTOCOL.md).

The simulator serves actions itself (an :class:`ActionServer` per name, registered with
``add_action``); a goal is known by the client's ``id`` of its ``send_action_goal``, which is the
id ``cancel_action_goal`` names. Every ``action_result`` carries ``status`` (action_msgs/GoalStatus
codes) and ``result`` (false when the goal was refused), as rosbridge sends them; a status is always
present because roslibpy 2.1 reads it from ``values`` otherwise and fails on a text value.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

from pmk_nb.sim.session import ClientSession, resolve_name

# action_msgs/msg/GoalStatus
STATUS_UNKNOWN, STATUS_ACCEPTED, STATUS_EXECUTING, STATUS_CANCELING = 0, 1, 2, 3
STATUS_SUCCEEDED, STATUS_CANCELED, STATUS_ABORTED = 4, 5, 6


@dataclass(frozen=True)
class GoalRef:
    """Where one action goal came from: the client, its goal id and the action name it used."""

    client: ClientSession
    goal_id: str
    action: str  # the client's spelling

    def feedback(self, values: dict[str, Any]) -> None:
        self.client.send_control({"op": "action_feedback", "id": self.goal_id, "action": self.action, "values": values})

    def result(self, status: int, values: dict[str, Any] | str, ok: bool = True) -> None:
        out = {"op": "action_result", "id": self.goal_id, "action": self.action, "values": values}
        self.client.send_control({**out, "status": status, "result": ok})


class ActionServer(Protocol):
    """What the bridge needs from an action the simulator serves."""

    def goal(self, ref: GoalRef, args: dict[str, Any]) -> None: ...

    def cancel(self, ref: GoalRef) -> None: ...

    def client_gone(self, client: ClientSession) -> None: ...


@dataclass
class ActionEntry:
    name: str
    type: str
    server: ActionServer


class ActionOps:
    """Mixin of :class:`pmk_nb.sim.protocol.Bridge`: the action registry and its two client ops."""

    actions: dict[str, ActionEntry]

    def add_action(self, name: str, type_name: str, server: ActionServer) -> None:
        self.actions[name] = ActionEntry(name, type_name, server)

    def _op_send_action_goal(self, client: ClientSession, msg: dict[str, Any]) -> None:
        spelled = str(msg["action"])
        ref = GoalRef(client, str(msg.get("id") or f"send_action_goal:{spelled}"), spelled)
        entry = self.actions.get(resolve_name(spelled))
        args = msg.get("args") or {}
        if entry is None:
            client.status("error", f"send_action_goal {spelled}: action does not exist", msg.get("id"))
            ref.result(STATUS_UNKNOWN, f"Action {spelled} does not exist", ok=False)
            return
        if not isinstance(args, dict):
            client.status("error", f"send_action_goal {spelled}: args must be a JSON object", msg.get("id"))
            ref.result(STATUS_UNKNOWN, "args must be a JSON object", ok=False)
            return
        entry.server.goal(ref, args)

    def _op_cancel_action_goal(self, client: ClientSession, msg: dict[str, Any]) -> None:
        spelled = str(msg["action"])
        entry = self.actions.get(resolve_name(spelled))
        if entry is None:
            client.status("warning", f"cancel_action_goal {spelled}: action does not exist", msg.get("id"))
            return
        entry.server.cancel(GoalRef(client, str(msg["id"]), spelled))

    def _drop_actions_of(self, client: ClientSession) -> None:
        for entry in self.actions.values():
            entry.server.client_gone(client)
