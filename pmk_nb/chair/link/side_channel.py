"""A second, short-lived websocket to the chair's rosbridge, for a Stop that must not wait.

rosbridge_suite 2.x handles one connection's messages on one thread (``IncomingQueue`` in
rosbridge_server's websocket_handler.py), and with ``send_action_goals_in_new_thread:=false`` (its
default) a running goal holds that thread: the link's own cancel and zero velocity wait behind the
goal. Its running goals sit in one dict shared by every connection
(``SendActionGoal.client_handler_list``, a class attribute in capabilities/send_action_goal.py), so
a ``cancel_action_goal`` naming the goal's id on another connection is handled at once, and that
connection's velocity commands are not held. The goal watch uses this when a cancel was not honoured.
"""

from __future__ import annotations

import json
import logging
import time

from pmk_nb.chair.messages import spell_type

LOG = logging.getLogger(__name__)
ZERO = {"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}


def side_stop(
    url: str,
    cmd_vel_topic: str,
    ros_version: int | None,
    cancel: tuple[str, str] | None,
    *,
    hz: float = 20.0,
    seconds: float = 1.0,
    timeout: float = 2.0,
) -> bool:
    """On a new connection to ``url``: cancel ``(action, goal id)`` when given, then zero velocity on
    ``cmd_vel_topic`` at ``hz`` for ``seconds``. Blocks that long; False when the chair could not be
    reached (the caller falls back to the link's own connection)."""
    import websockets.sync.client as ws_client
    from websockets.exceptions import WebSocketException

    twist = spell_type("geometry_msgs/Twist", ros_version)
    try:
        with ws_client.connect(url, open_timeout=timeout, close_timeout=1.0, compression=None) as ws:
            if cancel is not None:
                ws.send(json.dumps({"op": "cancel_action_goal", "id": cancel[1], "action": cancel[0]}))
            ws.send(json.dumps({"op": "advertise", "topic": cmd_vel_topic, "type": twist}))
            publish = json.dumps({"op": "publish", "topic": cmd_vel_topic, "msg": ZERO})
            for _ in range(max(1, round(hz * seconds))):
                ws.send(publish)
                time.sleep(1.0 / hz)
            ws.send(json.dumps({"op": "unadvertise", "topic": cmd_vel_topic}))
    except (OSError, TimeoutError, WebSocketException) as err:
        LOG.warning("side-channel stop to %s failed: %s", url, err)
        return False
    return True
