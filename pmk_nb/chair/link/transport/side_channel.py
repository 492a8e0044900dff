"""A second, short-lived websocket to the chair's rosbridge, for a Stop that must not wait.

rosbridge_suite 2.x handles one connection's messages on one thread (``IncomingQueue`` in
rosbridge_server's websocket_handler.py), and with ``send_action_goals_in_new_thread:=false`` (its
default) a running goal holds that thread: the link's own cancel and zero velocity wait behind the
goal. Its running goals sit in one dict shared by every connection
(``SendActionGoal.client_handler_list``, a class attribute in capabilities/send_action_goal.py), so
a ``cancel_action_goal`` naming the goal's id on another connection is handled at once, and that
connection's velocity commands are not held. The goal watch uses this when a cancel was not honoured,
and the goal heartbeat beats over one (its beats would otherwise wait behind the goal they vouch for).

A second connection speaks to the same chair as the link: same scheme, and over ``wss://`` the same
trust (CA file or pinned fingerprint, :mod:`pmk_nb.chair.link.transport.tls`), checked before anything is sent.
"""

from __future__ import annotations

import json
import logging
from typing import TYPE_CHECKING

from pmk_nb.chair.link.transport.tls import check_peer
from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.errors import ChairLinkError
from pmk_nb.wire import spell_type

if TYPE_CHECKING:
    from websockets.sync.client import ClientConnection

    from pmk_nb.chair.link.core import LinkCore

LOG = logging.getLogger(__name__)
ZERO = {"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}


SIDE_ERRORS: tuple[type[BaseException], ...] = (OSError, TimeoutError, ChairLinkError)


def side_connect(link: LinkCore, timeout: float = 2.0) -> ClientConnection:
    """A second websocket to ``link``'s chair, trusted as the link is; raises ``SIDE_ERRORS``
    (a websockets error is an OSError or wrapped below) when it cannot be opened or trusted."""
    import websockets.sync.client as ws_client
    from websockets.exceptions import WebSocketException

    host = f"[{link.host}]" if ":" in link.host else link.host
    url = f"{'wss' if link.tls else 'ws'}://{host}:{link.port}"
    context = link.tls.context() if link.tls else None
    try:
        ws = ws_client.connect(url, open_timeout=timeout, close_timeout=1.0, compression=None, ssl=context)
    except WebSocketException as err:
        raise OSError(f"second connection to {url}: {err}") from err
    ws.__enter__()  # websockets >= 17 warns about a connection used outside ``with``; the caller closes it
    if link.tls:
        try:
            check_peer(link.tls, link.host, link.port, ws.socket.getpeercert(binary_form=True))  # type: ignore[attr-defined]
        except ChairLinkError:
            ws.close()
            raise
    if link.auth is not None:  # a chair with rosbridge authentication hears nothing before it
        try:
            ws.send(json.dumps(link.auth.op(link.host, link.port)))
        except ChairLinkError:
            ws.close()
            raise
    return ws


def side_stop(
    link: LinkCore,
    cmd_vel_topic: str,
    cancel: tuple[str, str] | None,
    *,
    hz: float = 20.0,
    seconds: float = 1.0,
    timeout: float = 2.0,
    clock: Clock = MONOTONIC,
) -> bool:
    """On a new connection to ``link``'s chair: cancel ``(action, goal id)`` when given, then zero
    velocity on ``cmd_vel_topic`` at ``hz`` for ``seconds`` of ``clock``. Blocks that long; False when the chair
    could not be reached (the caller falls back to the link's own connection)."""
    from websockets.exceptions import WebSocketException

    errors: tuple[type[BaseException], ...] = (*SIDE_ERRORS, WebSocketException)
    twist = spell_type("geometry_msgs/Twist", link.ros_version)
    try:
        with side_connect(link, timeout) as ws:
            if cancel is not None:
                ws.send(json.dumps({"op": "cancel_action_goal", "id": cancel[1], "action": cancel[0]}))
            ws.send(json.dumps({"op": "advertise", "topic": cmd_vel_topic, "type": twist}))
            publish = json.dumps({"op": "publish", "topic": cmd_vel_topic, "msg": ZERO})
            for _ in range(max(1, round(hz * seconds))):
                ws.send(publish)
                clock.sleep(1.0 / hz)
            ws.send(json.dumps({"op": "unadvertise", "topic": cmd_vel_topic}))
    except errors as err:
        LOG.warning("side-channel stop to %s:%s failed: %s", link.host, link.port, err)
        return False
    return True
