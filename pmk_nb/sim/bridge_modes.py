"""Which real rosbridge server the simulator imitates for ROS 2 action goals (``pmk sim --bridge``).

``official``: rosbridge_suite 2.1.0 (the Python server most ROS 2 chairs run), read from its source
(github RobotWebTools/rosbridge_suite, branch ros2):

* a closed websocket does not cancel the client's action goals: ``SendActionGoal`` (rosbridge_library
  capabilities/send_action_goal.py) has no ``finish()``, so ``Protocol.finish`` (protocol.py) leaves
  its goals alone; the goal runs on;
* a goal the action server rejects is never answered: ``SendGoal.goal_response_cb``
  (internal/actions.py) raises "Action goal was rejected" inside rclpy's future callback, and
  ``SendGoal.send_goal`` then waits for a result forever;
* with ``send_action_goals_in_new_thread:=false`` (its launch file's default) ``send_action_goal`` runs on
  the client's ``IncomingQueue`` thread (rosbridge_server websocket_handler.py) until the goal ends,
  so every later op of that client (cancel_action_goal, publish on /cmd_vel, service calls) waits
  behind the goal; the cancel then finds no ``client_handler_list`` entry and does nothing. After a
  rejected goal the wait never ends: the client's ops are held until it reconnects;
* ``client_handler_list`` is a class attribute shared by every connection: a cancel naming a running
  goal's id works from another connection (e.g. the same client after a reconnect).

``rs``: rosbridge-server-rs 0.1.6 (the real ROS 2 test tier), measured against an rclpy
NavigateToPose action server: a closed websocket cancels the client's goals (the server saw the
cancel request 0.00 s after the close); a rejected goal is answered at once with status 6 (aborted),
``result: false`` and values "goal rejected" (no reason); a cancel reaches the server within 1 ms and
the answer is status 5 (canceled) with ``result: false``; a cancel naming the goal from another
connection is refused with a status "unknown active goal" (the goal ran on and succeeded).

The default is ``official``: the least optimistic of the two, and what most chairs run.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

BridgeMode = Literal["official", "rs"]
BRIDGE_MODES: tuple[BridgeMode, ...] = ("official", "rs")
DEFAULT_BRIDGE: BridgeMode = "official"
OFFICIAL_NODE = "/rosbridge_websocket"
NEW_THREAD_PARAM = "send_action_goals_in_new_thread"


@dataclass(frozen=True)
class BridgeFacts:
    """How one bridge treats action goals (see the module docstring)."""

    cancels_gone_clients_goals: bool
    answers_rejected_goals: bool
    ops_wait_behind_goal: bool
    cancel_from_any_client: bool  # a goal id's cancel works from another connection
    nodes: tuple[str, ...]  # what /rosapi/nodes lists besides the chair's own nodes


FACTS: dict[str, BridgeFacts] = {
    # rosbridge_suite's rosapi node makes a helper node "<rosapi>_params" (rosapi/params.py: init)
    # SendActionGoal.client_handler_list is a class attribute: one dict for every connection
    "official": BridgeFacts(False, False, True, True, (OFFICIAL_NODE, "/rosapi", "/rosapi_params")),
    "rs": BridgeFacts(True, True, False, False, (OFFICIAL_NODE,)),  # rosapi is served by the bridge itself
}


def facts(mode: str) -> BridgeFacts:
    return FACTS[mode]
