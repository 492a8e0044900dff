"""Who may reach the dashboard's server and its kernels: the Host, the Origin, one bounded channel per page.

Voilà's defaults trust every client that has the URL (issue 30): any ``Host`` header was served (DNS
rebinding: a web page on ``evil.example`` whose name later resolves to 127.0.0.1 could drive the
dashboard), a token-carrying websocket skipped the Origin check, and a page script could open more
websockets to its own kernel.  One such socket speaking the legacy JSON protocol and never reading
grew the server from 102 MB to 1.7 GB in 30 s (every live-view frame re-serialized and queued for
it), new pages got no answer, and its kernel outlived the page.  Both classes here are plugged in by
configuration (``voila.json``, :func:`pmk_nb.serve.voila.server_config`):

  * :class:`HostCheckingIdentityProvider` (``Voila.identity_provider_class``): a request whose Host
    is not one this server listens on (or, over HTTPS, one its certificate names) is refused (403),
    and an Origin is checked even when the request carries the token (jupyter_server compares the
    Origin's host:port with Host, so ``https://`` pages pass as ``http://`` ones do).
  * :class:`PageChannelConnection` (``Voila.kernel_websocket_connection_class``): a kernel has at
    most one websocket, the page's own (the first session that connected; a reconnect of that page
    is admitted once its old socket is closed); only the binary v1 protocol is spoken (the page's
    scripts always offer it); and a connection whose unsent output passes :data:`MAX_UNSENT_BYTES`
    is closed (nothing more is queued for it meanwhile).  Frames from the page reach the kernel only
    while its socket is admitted and open, and only when their header fits the frame
    (:mod:`pmk_nb.serve.voila_frames`): jupyter_server parses a closed socket's frames with its legacy
    deserializer, which trusts a buffer count (one 68-byte frame: +270 MB, kept).

The refusals are what bound the server: with them switched off in an experiment, a silent legacy
socket grew the server from 100 to 265 MB in 12 s although only one message went through its
``write_message`` (the growth is queued before the websocket, in the connection's own ZMQ channels),
and the output budget never tripped.  The budget is a back-stop for the page's own socket only.

This module is the one seam to jupyter_server's kernel-websocket internals (``ZMQChannelsWebsocketConnection``'s
``prepare``/``connect``/``disconnect``/``write_message``/``handle_incoming_message``, ``_open_sessions``);
tests/kernels/test_voila_guard_seam.py pins them in the installed version.
"""

from __future__ import annotations

import asyncio
import ipaddress
import re
import socket
from functools import lru_cache
from typing import Any, ClassVar

from jupyter_server.auth.identity import PasswordIdentityProvider
from jupyter_server.services.kernels.connection.channels import ZMQChannelsWebsocketConnection
from tornado import web

from pmk_nb.seams import forget_open_session
from pmk_nb.serve.serving import DEFAULT_IP, server_names
from pmk_nb.serve.voila_frames import v1_frame_fault

V1_PROTOCOL = "v1.kernel.websocket.jupyter.org"
#: unsent bytes after which a kernel websocket is closed.  The page itself stays within a second and
#: a half of the kernel's output (page_lifecycle's flow control: a few MB at most, a map image included)
MAX_UNSENT_BYTES = 32 * 1024 * 1024
POLICY_VIOLATION = 1008  # websocket close code
ANY_ADDRESS = ("0.0.0.0", "", "::")
LOOPBACK_NAMES = ("localhost", "127.0.0.1", "::1")


def request_host(host_header: str) -> str:
    """The host part of a ``Host`` header, lower case, without port or IPv6 brackets."""
    match = re.match(r"^\[([^\]]*)\](:\d+)?$|^([^:]*)(:\d+)?$", host_header.strip())
    if match is None:
        return host_header.strip().lower()  # a bare IPv6 address, or garbage (compared as is)
    return (match.group(1) or match.group(3) or "").lower()


@lru_cache(maxsize=64)
def is_own_address(host: str) -> bool:
    """Whether ``host`` is an IP address of this machine (it can be bound to)."""
    try:
        addr = ipaddress.ip_address(host)
    except ValueError:
        return False
    family = socket.AF_INET6 if addr.version == 6 else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as sock:
        try:
            sock.bind((str(addr), 0))
        except OSError:
            return False
    return True


def host_allowed(host: str, listen_ip: str, names: list[str]) -> bool:
    """``host`` (from :func:`request_host`) names this server: a loopback address or name, the address
    it listens on, one of ``names`` (the machine's own names when serving the LAN), or, listening on
    every interface, any address of this machine."""
    if not host:
        return False
    if host in LOOPBACK_NAMES or host in names or host == listen_ip.lower():
        return True
    try:
        if ipaddress.ip_address(host).is_loopback:
            return True
    except ValueError:
        return False  # a name we were not told about: what DNS rebinding sends
    return listen_ip in ANY_ADDRESS and is_own_address(host)


class OutputBudget:
    """Bytes queued on a websocket and not yet sent; over ``limit``, nothing more is queued."""

    def __init__(self, limit: int = MAX_UNSENT_BYTES) -> None:
        self.limit = limit
        self.unsent = 0

    def over(self) -> bool:
        return self.unsent > self.limit

    def queued(self, size: int) -> None:
        self.unsent += size

    def sent(self, size: int) -> None:
        self.unsent = max(0, self.unsent - size)


@lru_cache(maxsize=4)
def _names(ip: str) -> list[str]:
    return server_names(ip)


@lru_cache(maxsize=4)
def certificate_hosts(certfile: str) -> tuple[str, ...]:
    """The names and addresses the served certificate vouches for (lower case): a browser reaches this
    server by them without a warning, so they are its own (a lab's certificate for ``pmk.ward.example``)."""
    from cryptography import x509

    from pmk_nb.serve.tablet_tls import certificate_names

    with open(certfile, "rb") as fh:
        cert = x509.load_pem_x509_certificate(fh.read())
    return tuple(n.lower() for n in certificate_names(cert))


class HostCheckingIdentityProvider(PasswordIdentityProvider):
    """Voilà's identity provider, refusing foreign ``Host`` headers and checking Origin even with the token.

    The address it listens on is Voilà's own ``ip`` (this provider's parent is the Voilà app)."""

    @property
    def listen_ip(self) -> str:
        return str(getattr(self.parent, "ip", None) or DEFAULT_IP)

    @property
    def names(self) -> list[str]:
        """The machine's names (serving the LAN) and, over HTTPS, the names in the served certificate."""
        tls = (getattr(self.parent, "tornado_settings", None) or {}).get("ssl_options") or {}
        served = certificate_hosts(str(tls["certfile"])) if tls.get("certfile") else ()
        return [*_names(self.listen_ip), *served]

    def get_user(self, handler: web.RequestHandler) -> Any:
        host = request_host(handler.request.headers.get("Host", ""))
        if not host_allowed(host, self.listen_ip, self.names):
            self.log.warning("Refused a request for Host %r (not this server: DNS rebinding?)", host[:100])
            raise web.HTTPError(403)
        return super().get_user(handler)

    def should_check_origin(self, handler: web.RequestHandler) -> bool:
        """Always: a token in the URL is no proof that the request comes from our own page."""
        return True


class PageChannelConnection(ZMQChannelsWebsocketConnection):
    """A kernel's websocket: the page's own only, v1 protocol only, output bounded (see the module doc)."""

    _channels: ClassVar[dict[str, PageChannelConnection]] = {}  # kernel id -> its open, admitted channel
    _page_sessions: ClassVar[dict[str, str]] = {}  # kernel id -> the session id of its page

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._admitted = False
        self.budget = OutputBudget()
        self._overflowed = False

    def _refusal(self) -> tuple[int, str] | None:
        """(HTTP status, why) when this connection may not have the kernel; None when it may."""
        offered = self.websocket_handler.request.headers.get("Sec-WebSocket-Protocol", "")
        if V1_PROTOCOL not in [p.strip() for p in offered.split(",")]:
            return 400, "the legacy protocol is not served"
        page = self._page_sessions.get(self.kernel_id)
        if page is not None and page != self.session.session:
            return 409, "another page's session"
        if self.kernel_id in self._channels:
            return 409, "the kernel already has its page's channel"
        return None

    async def prepare(self) -> None:
        refusal = self._refusal()
        if refusal is not None:
            self.multi_kernel_manager.log.warning("Kernel %s: refused a websocket (%s)", self.kernel_id, refusal[1])
            raise web.HTTPError(*refusal)
        await super().prepare()  # type: ignore[no-untyped-call]  # jupyter_server: unannotated

    def connect(self) -> asyncio.Future[None] | None:  # type: ignore[override]
        refusal = self._refusal()  # again: another socket may have been admitted while this one was prepared
        if refusal is not None:
            self.multi_kernel_manager.log.warning("Kernel %s: closed a websocket (%s)", self.kernel_id, refusal[1])
            self.websocket_handler.close(POLICY_VIOLATION, refusal[1])
            done: asyncio.Future[None] = asyncio.get_running_loop().create_future()
            done.set_result(None)
            return done
        known = set(self.multi_kernel_manager.list_kernel_ids())
        for table in (self._channels, self._page_sessions):
            for kid in [k for k in table if k not in known]:
                table.pop(kid, None)
        self._admitted = True
        self._channels[self.kernel_id] = self
        self._page_sessions.setdefault(self.kernel_id, self.session.session)
        return super().connect()

    # the ZMQ connection this extends disconnects synchronously; its base class declares a coroutine
    def disconnect(self) -> None:  # type: ignore[override]
        if not self._admitted:  # refused in connect(): it never counted as a connection
            forget_open_session(self)
            return
        if self._channels.get(self.kernel_id) is self:
            self._channels.pop(self.kernel_id, None)
        self._admitted = False
        socket_closed = getattr(self.multi_kernel_manager, "socket_closed", None)  # the page-bound manager's
        if socket_closed is not None:
            socket_closed(self.kernel_id, self.websocket_handler.close_code)
        super().disconnect()  # type: ignore[no-untyped-call]  # jupyter_server: unannotated

    def handle_incoming_message(self, incoming_msg: Any) -> None:
        """Pass a frame from the page on to the kernel only while this socket is admitted and open, and
        only a v1 frame whose header fits it (:func:`~pmk_nb.serve.voila_frames.v1_frame_fault`).

        Once the server closed the socket (a ping timeout, :meth:`_bounded_write`), jupyter_server reads
        the subprotocol as None and parses what still arrives with its legacy deserializer: one 68-byte
        frame then grew Voilà by 270 MB for good.  Those frames are dropped here, unread; a malformed
        frame closes the socket."""
        if not (self._admitted and self._open()):
            return
        fault = v1_frame_fault(incoming_msg)
        if fault is not None:
            log = self.multi_kernel_manager.log
            log.warning("Kernel %s: a websocket sent a malformed frame (%s); closing it", self.kernel_id, fault.value)
            self.websocket_handler.close(POLICY_VIOLATION, "malformed frame")
            return
        super().handle_incoming_message(incoming_msg)

    def _open(self) -> bool:
        """The websocket is open, in the v1 protocol, and not closing (no close frame sent or received)."""
        ws = self.websocket_handler.ws_connection
        return ws is not None and not ws.is_closing() and self.subprotocol == V1_PROTOCOL

    @property
    def write_message(self) -> Any:
        """The handler's ``write_message``, counting what is not yet sent (see :meth:`_bounded_write`)."""
        return self._bounded_write

    def _bounded_write(self, message: bytes | str | dict[str, Any], binary: bool = False) -> Any:
        """Queue ``message`` unless this socket is :data:`MAX_UNSENT_BYTES` behind; then close it."""
        handler = self.websocket_handler
        if self.budget.over():
            if not self._overflowed:
                self._overflowed = True
                behind = self.budget.unsent >> 20
                log = self.multi_kernel_manager.log  # (this object's own logger is not Voilà's)
                log.warning("Kernel %s: a websocket %d MB behind; closing it", self.kernel_id, behind)
                handler.close(POLICY_VIOLATION, "too far behind")
            return None
        future = handler.write_message(message, binary)
        if future is None:  # Voilà drops some messages (execute_input)
            return None
        size = len(message) if isinstance(message, bytes | str) else 0
        self.budget.queued(size)
        future.add_done_callback(lambda f: self._written(f, size))
        return future

    def _written(self, future: asyncio.Future[Any], size: int) -> None:
        self.budget.sent(size)
        if not future.cancelled():
            future.exception()  # a closed socket: retrieved, not logged as "never retrieved"
