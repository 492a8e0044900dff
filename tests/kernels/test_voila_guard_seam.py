"""The Voilà / jupyter_server internals pmk_nb.serve.voila_guard relies on are still there, in the installed versions.

Each test fails when a release moves one of them, before a guard silently stops guarding.
"""

from __future__ import annotations

import inspect

from jupyter_server.auth.identity import PasswordIdentityProvider
from jupyter_server.base import handlers as base_handlers
from jupyter_server.base import websocket as base_websocket
from jupyter_server.services.kernels import websocket as kernel_websocket
from jupyter_server.services.kernels.connection import channels
from tornado import websocket
from voila import app as voila_app

from pmk_nb.serve.voila_guard import V1_PROTOCOL, HostCheckingIdentityProvider, PageChannelConnection


def test_voila_takes_both_classes_from_its_config() -> None:
    source = inspect.getsource(voila_app.Voila.init_settings)
    assert "self.identity_provider_class(" in source
    assert '"kernel_websocket_connection_class": self.kernel_websocket_connection_class' in source
    for trait in ("identity_provider_class", "kernel_websocket_connection_class", "tornado_settings"):
        assert voila_app.Voila.class_traits()[trait].metadata.get("config"), trait
    # our tornado_settings (allow_remote_access) are applied after Voilà's own settings
    assert "self.app.settings.update(self.tornado_settings)" in inspect.getsource(voila_app.Voila.start)


def test_every_request_asks_the_identity_provider_and_websockets_check_origin_through_it() -> None:
    prepare = inspect.getsource(base_handlers.JupyterHandler.prepare)
    assert "self.check_host()" in prepare and "self.identity_provider.get_user(self)" in prepare
    assert "should_check_origin" in inspect.getsource(base_handlers.JupyterHandler.skip_check_origin)
    assert "skip_check_origin" in inspect.getsource(base_websocket.WebSocketMixin.check_origin)
    assert issubclass(HostCheckingIdentityProvider, PasswordIdentityProvider)


def test_the_handler_prepares_its_connection_with_the_session_before_the_upgrade() -> None:
    pre_get = inspect.getsource(kernel_websocket.KernelWebsocketHandler.pre_get)
    assert pre_get.index("connection.session.session") < pre_get.index("await self.connection.prepare()")
    get = inspect.getsource(kernel_websocket.KernelWebsocketHandler.get)
    assert get.index("await self.pre_get()") < get.index("await super().get(")  # refusals are HTTP errors
    assert "await self.connection.connect()" in inspect.getsource(kernel_websocket.KernelWebsocketHandler.open)
    assert "self.connection.disconnect()" in inspect.getsource(kernel_websocket.KernelWebsocketHandler.on_close)
    selected = inspect.getsource(kernel_websocket.KernelWebsocketHandler.select_subprotocol)
    assert "v1.kernel.websocket.jupyter.org" in selected and V1_PROTOCOL == "v1.kernel.websocket.jupyter.org"


def test_every_write_to_the_page_goes_through_the_connections_write_message() -> None:
    source = inspect.getsource(channels.ZMQChannelsWebsocketConnection)
    assert source.count("websocket_handler.write_message") == 1  # only in the write_message property
    assert isinstance(inspect.getattr_static(channels.ZMQChannelsWebsocketConnection, "write_message"), property)
    assert isinstance(inspect.getattr_static(PageChannelConnection, "write_message"), property)
    for name in ("prepare", "connect", "disconnect", "_open_sessions", "session_key"):
        assert hasattr(channels.ZMQChannelsWebsocketConnection, name) or name in source, name
    assert "notify_connect" in inspect.getsource(channels.ZMQChannelsWebsocketConnection.connect)
    assert "notify_disconnect" in inspect.getsource(channels.ZMQChannelsWebsocketConnection.disconnect)


def test_frames_from_the_page_enter_through_handle_incoming_message_and_a_closed_socket_reads_as_legacy() -> None:
    """Why PageChannelConnection drops a closed socket's frames: tornado lets go of the protocol on the
    server's close but still hands the page's frames to ``on_message`` until the connection ends, and
    jupyter_server then reads the subprotocol as None and parses them with its legacy deserializer."""
    assert "self.connection.handle_incoming_message(" in inspect.getsource(
        kernel_websocket.KernelWebsocketHandler.on_message
    )
    incoming = inspect.getsource(channels.ZMQChannelsWebsocketConnection.handle_incoming_message)
    assert "deserialize_msg_from_ws_v1(ws_msg)" in incoming and "deserialize_binary_message(ws_msg)" in incoming
    subprotocol = inspect.getsource(channels.ZMQChannelsWebsocketConnection.subprotocol.fget)
    assert "self.websocket_handler.selected_subprotocol" in subprotocol and "protocol = None" in subprotocol
    close = inspect.getsource(websocket.WebSocketHandler.close)
    assert "self.ws_connection = None" in close
    assert "assert self.ws_connection is not None" in inspect.getsource(
        websocket.WebSocketHandler.selected_subprotocol.fget
    )
    assert "self._run_callback(self.handler.on_message" in inspect.getsource(
        websocket.WebSocketProtocol13._handle_message
    )
    assert callable(websocket.WebSocketProtocol.is_closing)
    assert "handle_incoming_message" in PageChannelConnection.__dict__
