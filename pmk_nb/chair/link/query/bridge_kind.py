"""Which rosbridge server a ROS 2 chair runs, as far as its goals are concerned (issue 24).

rosbridge_suite 2.x (the Python server) is told apart by its rosapi: the rosapi node makes a helper
node named ``<rosapi>_params`` (rosapi/params.py: ``init``), so ``/rosapi/nodes`` lists
``/rosapi_params``; rosbridge-server-rs answers rosapi itself and lists no such node. Then its
``send_action_goals_in_new_thread`` parameter is read through ``/rosapi/get_param``
(``/rosbridge_websocket:send_action_goals_in_new_thread``; unset or unreadable means the launch
file's default, false). What follows from it is in :mod:`pmk_nb.sim.bridge_modes`: rosbridge_suite
keeps a lost client's goals and never answers a rejected goal; without new threads it also handles
a cancel only after the goal has ended.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import TYPE_CHECKING

from pmk_nb.errors import ChairLinkError

if TYPE_CHECKING:
    from pmk_nb.chair.link.core import LinkCore

SUITE_MARK = "/rosapi_params"
NEW_THREAD_PARAM = "/rosbridge_websocket:send_action_goals_in_new_thread"


@dataclass(frozen=True)
class BridgeKind:
    """``name``: "rosbridge_suite", "other" (e.g. rosbridge-server-rs) or "unknown" (no rosapi)."""

    name: str
    goals_in_new_thread: bool | None = None

    @property
    def ignores_cancels(self) -> bool:
        """True: a cancel waits behind the running goal (rosbridge_suite's default)."""
        return self.name == "rosbridge_suite" and not self.goals_in_new_thread

    @property
    def keeps_lost_goals(self) -> bool:
        return self.name == "rosbridge_suite"


def detect_bridge(link: LinkCore, timeout: float = 2.0) -> BridgeKind:
    """Ask rosapi (see the module docstring); "unknown" when rosapi does not answer."""
    try:
        nodes = link.call("/rosapi/nodes", "rosapi_msgs/srv/Nodes", {}, timeout).get("nodes") or []
    except ChairLinkError:
        return BridgeKind("unknown")
    if SUITE_MARK not in nodes:
        return BridgeKind("other")
    try:
        args = {"name": NEW_THREAD_PARAM, "default_value": ""}
        raw = link.call("/rosapi/get_param", "rosapi_msgs/srv/GetParam", args, timeout).get("value")
        value = json.loads(raw) if isinstance(raw, str) and raw else None
    except (ChairLinkError, ValueError):
        value = None
    return BridgeKind("rosbridge_suite", value if isinstance(value, bool) else None)
