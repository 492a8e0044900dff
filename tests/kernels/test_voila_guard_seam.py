"""The Voilà / jupyter_server internals pmk_nb.cli.voila_guard relies on are still there, in the installed versions.

Each test fails when a release moves one of them, before a guard silently stops guarding.
"""

from __future__ import annotations

import inspect

from jupyter_server.auth.identity import PasswordIdentityProvider
from jupyter_server.base import handlers as base_handlers
from jupyter_server.base import websocket as base_websocket
from jupyter_server.services.kernels import websocket as kernel_websocket
from jupyter_server.services.kernels.connection import channels
from voila import app as voila_app

from pmk_nb.cli.voila_guard import V1_PROTOCOL, HostCheckingIdentityProvider, PageChannelConnection


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
