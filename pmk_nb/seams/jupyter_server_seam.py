"""jupyter_server internals (pinned: jupyter_server==2.21.1; tests/seams/test_jupyter_server_seam.py).

Touched: ``MappingKernelManager._kernel_connections`` (kernel id -> open websockets, kept by its
``notify_connect`` / ``notify_disconnect``: the only count of a kernel's pages) and
``ZMQChannelsWebsocketConnection._open_sessions`` (session key -> websocket handler, a class-wide
table a refused connection must leave, or the page's next socket is taken for a duplicate).
"""

from __future__ import annotations

from typing import Any

TOUCHED = ("_kernel_connections", "_open_sessions")


def kernel_connections(manager: Any, kernel_id: str, default: int = 1) -> int:
    """How many websockets ``kernel_id`` has open, as the kernel manager counts them."""
    return int(manager._kernel_connections.get(kernel_id, default))


def forget_open_session(connection: Any) -> None:
    """Drop ``connection``'s entry in the open-sessions table if it is still its own."""
    sessions = connection._open_sessions
    if sessions.get(connection.session_key) is connection.websocket_handler:
        sessions.pop(connection.session_key, None)
