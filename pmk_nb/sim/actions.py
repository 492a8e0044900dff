"""rosbridge ROS 2 action ops: ``send_action_goal`` and ``cancel_action_goal`` in, ``action_feedback``
and ``action_result`` out (rosbridge 2.0's ROSBRIDGE_PROTOCOL.md).

The simulator serves actions itself (an :class:`ActionServer` per name, registered with
``add_action``); a goal is known by the client's ``id`` of its ``send_action_goal``, which is the
id ``cancel_action_goal`` names. Every ``action_result`` carries ``status`` (action_msgs/GoalStatus
codes) and ``result`` (false when the goal was refused), as rosbridge sends them; a status is always
present because roslibpy 2.1 reads it from ``values`` otherwise and fails on a text value.

The bridge mode (:mod:`pmk_nb.sim.bridge_modes`) decides what a rejection and a closed socket do,
and whether the client's later ops wait behind its goal (``official``: they are held in
``ClientSession.held`` until the goal's result went out, for ever after a rejection).
"""

from __future__ import annotations

import uuid
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol

from pmk_nb.sim.bridge_modes import BridgeFacts, facts
from pmk_nb.sim.session import ClientSession, resolve_name
from pmk_nb.wire import STATUS_ABORTED as STATUS_ABORTED  # navigation reads the codes here, as a2.STATUS_*
from pmk_nb.wire import STATUS_ACCEPTED as STATUS_ACCEPTED
from pmk_nb.wire import STATUS_CANCELED as STATUS_CANCELED
from pmk_nb.wire import STATUS_CANCELING as STATUS_CANCELING
from pmk_nb.wire import STATUS_EXECUTING as STATUS_EXECUTING
from pmk_nb.wire import STATUS_SUCCEEDED as STATUS_SUCCEEDED
from pmk_nb.wire import STATUS_UNKNOWN as STATUS_UNKNOWN

# action_msgs/msg/GoalStatus


@dataclass(frozen=True)
class GoalRef:
    """Where one action goal came from: the client, its goal id and the action name it used."""

    client: ClientSession
    goal_id: str
    action: str  # the client's spelling
    answers_rejects: bool = True  # False: rosbridge_suite, which never answers a rejected goal
    on_result: Callable[[], None] | None = None  # the bridge releases the client's held ops
    uuid: tuple[int, ...] = field(default_factory=lambda: tuple(uuid.uuid4().bytes))  # the action's goal id

    def feedback(self, values: dict[str, Any]) -> None:
        self.client.send_control({"op": "action_feedback", "id": self.goal_id, "action": self.action, "values": values})

    def result(self, status: int, values: dict[str, Any] | str, ok: bool = True) -> None:
        out = {"op": "action_result", "id": self.goal_id, "action": self.action, "values": values}
        self.client.send_control({**out, "status": status, "result": ok})
        if self.on_result is not None:
            self.on_result()

    def reject(self) -> None:
        """The action server refused the goal: answered as rosbridge-server-rs 0.1.6 does (measured:
        status 6, ``result: false``, values "goal rejected", no reason), or silence for ever
        (rosbridge_suite: ``SendGoal.goal_response_cb`` raises inside rclpy's callback, internal/actions.py)."""
        if self.answers_rejects:
            self.result(STATUS_ABORTED, "goal rejected", ok=False)


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
    bridge_facts: BridgeFacts = facts("rs")

    dispatch: Callable[[ClientSession, str], None]

    def receive(self, client: ClientSession, raw: str) -> None:
        """One incoming message: handled now, or held behind the client's running goal (official)."""
        if client.held is not None:
            client.held.append(raw)
        else:
            self.dispatch(client, raw)

    def _release(self, client: ClientSession) -> None:
        """The goal the client's ops waited behind has ended: handle them in order (a next goal holds again)."""
        held, client.held = client.held, None
        while held:
            raw = held.popleft()
            if client.held is not None:
                client.held.extend([raw, *held])
                return
            self.dispatch(client, raw)

    def add_action(self, name: str, type_name: str, server: ActionServer) -> None:
        self.actions[name] = ActionEntry(name, type_name, server)

    def _op_send_action_goal(self, client: ClientSession, msg: dict[str, Any]) -> None:
        spelled = str(msg["action"])
        ref = GoalRef(client, str(msg.get("id") or f"send_action_goal:{spelled}"), spelled)
        entry = self.actions.get(resolve_name(spelled))
        args = msg.get("args") or {}
        if self.bridge_facts.ops_wait_behind_goal:  # rosbridge_suite: this client's IncomingQueue waits
            client.held = deque()
            release = lambda: self._release(client)  # noqa: E731
            ref = GoalRef(client, ref.goal_id, spelled, self.bridge_facts.answers_rejected_goals, release)
        if entry is None:
            client.status("error", f"send_action_goal {spelled}: action does not exist", msg.get("id"))
            if self.bridge_facts.answers_rejected_goals:
                ref.result(STATUS_UNKNOWN, f"Action {spelled} does not exist", ok=False)
            return  # rosbridge_suite: no server, no goal response, the wait never ends
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

    def drop_actions_of(self, client: ClientSession) -> None:
        client.held = None  # IncomingQueue.finish: queued ops are dropped
        if not self.bridge_facts.cancels_gone_clients_goals:
            return  # rosbridge_suite: SendActionGoal has no finish(); the goals run on
        for entry in self.actions.values():
            entry.server.client_gone(client)
