"""The jupyter_server internals pmk_nb/seams/jupyter_server_seam.py reads are still there, in the pinned version."""

from __future__ import annotations

import inspect
from types import SimpleNamespace

from jupyter_server.services.kernels.connection.channels import ZMQChannelsWebsocketConnection
from jupyter_server.services.kernels.kernelmanager import AsyncMappingKernelManager, MappingKernelManager

from pmk_nb.seams.jupyter_server_seam import TOUCHED, forget_open_session, kernel_connections
from tests.seam_pins import assert_pinned_and_installed


def test_installed_jupyter_server_is_the_pinned_version() -> None:
    assert_pinned_and_installed("jupyter_server")


def test_the_kernel_manager_still_counts_websockets_in_kernel_connections() -> None:
    assert TOUCHED == ("_kernel_connections", "_open_sessions")
    assert "self._kernel_connections[kernel_id] += 1" in inspect.getsource(MappingKernelManager.notify_connect)
    assert "self._kernel_connections[kernel_id] -= 1" in inspect.getsource(MappingKernelManager.notify_disconnect)
    manager = AsyncMappingKernelManager()
    manager._kernel_connections["k1"] = 0
    manager.notify_connect("k1")
    assert kernel_connections(manager, "k1") == 1
    manager.notify_disconnect("k1")
    assert kernel_connections(manager, "k1") == 0 and kernel_connections(manager, "unknown") == 1


def test_open_sessions_is_still_the_class_wide_table_of_connections() -> None:
    assert isinstance(ZMQChannelsWebsocketConnection._open_sessions, dict)
    register = inspect.getsource(ZMQChannelsWebsocketConnection._register_session)
    assert "self._open_sessions[self.session_key] = self.websocket_handler" in register
    disconnect = inspect.getsource(ZMQChannelsWebsocketConnection.disconnect)
    assert "if self._open_sessions.get(self.session_key) is self.websocket_handler:" in disconnect
    handler, other = object(), object()
    table = {"s1": handler, "s2": other}
    forget_open_session(SimpleNamespace(_open_sessions=table, session_key="s1", websocket_handler=handler))
    forget_open_session(SimpleNamespace(_open_sessions=table, session_key="s2", websocket_handler=handler))
    assert table == {"s2": other}  # only its own entry goes
