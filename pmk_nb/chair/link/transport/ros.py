"""A roslibpy ``Ros`` on its own asyncio loop thread, so one link can be closed and reopened.

roslibpy's asyncio transport shares one process-wide loop between all ``Ros`` objects, and
``terminate()`` stops it for everyone (the Twisted transport cannot even restart its reactor). A
chair link must release its thread on ``close()`` and connect again later in the same kernel, and
two chairs must not share one I/O thread. So each link builds roslibpy's own factory on a private
loop manager (:mod:`pmk_nb.chair.link.transport.factory`); topics, services and reconnects are roslibpy's.

Transport choice: Autobahn (under both of roslibpy's transports) can use only one of Twisted and
asyncio per process (txaio: "Explicitly using 'twisted' already"), and plain ``roslibpy.Ros(host,
port)`` picks Twisted unless told otherwise. A link therefore follows the process, in either order
(decided in :mod:`.framework`, the one place that picks):

* nothing bound yet: importing this module makes asyncio roslibpy's default through its public
  ``set_default_transport`` (unless ``ROSLIBPY_TRANSPORT`` decides), so a plain ``roslibpy.Ros``
  created later shares asyncio with the links;
* Twisted already bound (a plain ``roslibpy.Ros`` came first, or any Autobahn/Twisted library): the
  link runs on roslibpy's Twisted transport instead (:mod:`pmk_nb.chair.link.transport.factory_twisted`), on
  the process's one reactor thread.

Nothing binds a framework until a link connects.

roslibpy internals (``Ros._id_counter``, since ``Ros.__init__`` is not called: it builds its factory on
the process-wide loop, starting that loop's thread, and connects at once; the protocol's ``status``
handler; the factory's) are touched only in :mod:`pmk_nb.seams.roslibpy_seam` (pinned version,
checked by ``tests/seams/test_roslibpy_seam.py``).
"""

from __future__ import annotations

import collections
import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import roslibpy

from pmk_nb.chair.link.transport.bridge_auth import BridgeAuthError
from pmk_nb.chair.link.transport.framework import factory_module
from pmk_nb.errors import ChairLinkError
from pmk_nb.seams import init_id_counter, install_status_handler

if TYPE_CHECKING:
    from pmk_nb.chair.link.transport.bridge_auth import BridgeAuth
    from pmk_nb.chair.link.transport.factory import LinkFactory
    from pmk_nb.chair.link.transport.tls import ChairTls

STATUS_KEPT = 20


@dataclass(frozen=True)
class ServerStatus:
    """One rosbridge ``status`` message: level ("error", "warning", "info"), text, request id."""

    level: str
    msg: str
    id: str = ""


#: Why a wss link cannot run on the Twisted transport (its TLS check is the asyncio factory's).
_TWISTED_TLS = (
    "TLS (wss) to the chair needs roslibpy's asyncio transport, but this process already uses Twisted "
    "(a plain roslibpy.Ros was created first): open the chair link before any other roslibpy connection"
)


class LinkRos(roslibpy.Ros):  # type: ignore[misc]  # roslibpy has no type hints: subclassing it is the seam
    """``roslibpy.Ros`` that owns its event-loop thread (on asyncio; on Twisted it shares the reactor).

    Use :meth:`shutdown` (not ``terminate``) to close the socket and stop the thread.
    """

    def __init__(
        self,
        host: str,
        port: int,
        *,
        thread_name: str,
        initial_delay: float = 0.5,
        max_delay: float = 10.0,
        ping_interval: float = 5.0,
        ping_timeout: float = 5.0,
        tls: ChairTls | None = None,
        auth: BridgeAuth | None = None,
    ) -> None:
        module = factory_module()
        self.factory_chair = (host, port)
        self.auth_failure: BridgeAuthError | None = None
        init_id_counter(self)  # what Ros.__init__ would set (see the module docstring)
        extra: dict[str, Any] = {}
        if module.__name__.endswith("twisted"):
            if tls is not None:
                raise ChairLinkError(_TWISTED_TLS, host=host, port=port)
            self.manager, self.loop_thread = module.start_loop(thread_name)
            factory_cls = module.TwistedLinkFactory
        else:
            self.manager, self.loop_thread = module.start_private_loop(thread_name)
            factory_cls = module.LinkFactory
            extra = {"tls": tls, "chair": (host, port)}
        self.factory: LinkFactory = factory_cls(
            factory_cls.create_url(host, port, tls is not None),
            self.manager,
            initial_delay=initial_delay,
            max_delay=max_delay,
            ping_interval=ping_interval,
            ping_timeout=ping_timeout,
            **extra,
        )
        self.auth = auth
        if auth is not None:  # first of all "ready" listeners: the auth op goes before any other op
            self.factory.on("ready", self._send_auth)
        # set once the websocket opened or the chair's TLS certificate was refused (``refusal``)
        self.settled = threading.Event()
        self.factory.on("ready", lambda _proto: self.settled.set())
        self.factory.on("refused", lambda _err: self.settled.set())
        self.is_connecting = False
        self.protocol: Any = None  # the open websocket protocol, from the factory's events
        self.statuses: collections.deque[ServerStatus] = collections.deque(maxlen=STATUS_KEPT)
        self.factory.on("ready", self._track_protocol)
        self.factory.on("close", self._drop_protocol)

    @property
    def refusal(self) -> ChairLinkError | None:
        """Why the chair's TLS certificate was refused on this link's own socket, if it was."""
        return getattr(self.factory, "refusal", None)

    def _send_auth(self, proto: Any) -> None:
        """rosbridge's ``auth`` op on every (re)connect, fresh each time (rosauth checks its time)."""
        assert self.auth is not None
        host, port = self.factory_chair
        try:
            proto.send_ros_message(roslibpy.Message(self.auth.op(host, port)))
        except BridgeAuthError as err:  # unreadable secret: the chair will close the socket on our first op
            self.auth_failure = err

    def _track_protocol(self, proto: Any) -> None:
        self.protocol = proto
        install_status_handler(proto, self._on_status)  # roslibpy leaves it None ("TODO")

    def _on_status(self, message: Any) -> None:
        """The server's ``status`` op (errors and warnings about our requests, e.g. a wrong topic
        type): kept for the user (roslibpy has no handler and would log a traceback)."""
        self.statuses.append(
            ServerStatus(str(message.get("level", "")), str(message.get("msg", "")), str(message.get("id", "")))
        )

    def _drop_protocol(self, proto: Any) -> None:
        if self.protocol is proto:
            self.protocol = None

    def shutdown(self, timeout: float = 2.0) -> None:
        """Stop reconnecting, close the websocket, stop and join the loop thread (bounded by ``timeout``;
        on Twisted the process's reactor thread keeps running)."""
        deadline = time.monotonic() + timeout
        self.factory.stop_reconnecting()  # no reconnect after the close below
        if not self.factory.loop_alive():
            return
        proto = self.protocol
        if proto is not None:
            closed = threading.Event()
            self.factory.once("close", lambda *_: closed.set())
            proto.send_close()
            # A half-open peer never answers the close handshake: do not wait for it long.
            closed.wait(max(0.0, min(deadline - time.monotonic(), timeout / 2)))
        self.factory.abort(self, deadline - time.monotonic())
