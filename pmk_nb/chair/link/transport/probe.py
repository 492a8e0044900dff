"""Find out precisely why a chair cannot be reached, within a hard time budget.

roslibpy retries failed connects silently (the cause is only logged), so before handing a host to
it the link probes it step by step with a plain socket and a synchronous websocket client:
DNS -> TCP -> websocket handshake -> one rosbridge request. Each step has its own reason string,
which is what the settings screen shows (the original app only ever said "disconnected").

A server that completed the websocket handshake but sends nothing at all cannot be told from a
rosbridge busy encoding a big ``/map``: that is reported as "timed out" (with both causes named),
never as "not a rosbridge server", which is kept for servers that answer something else.
"""

from __future__ import annotations

import dataclasses
import json
import socket
import ssl
import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

from websockets.exceptions import (
    ConnectionClosed,
    InvalidHandshake,
    InvalidStatus,
    WebSocketException,
)
from websockets.sync.client import connect as ws_connect

from pmk_nb.chair.link.transport.bridge_auth import BridgeAuth, BridgeAuthError
from pmk_nb.chair.link.transport.tls import check_peer, handshake_failure
from pmk_nb.errors import ChairCertificateError

#: one getaddrinfo answer: (family, type, proto, canonname, sockaddr)
AddrInfo = tuple[socket.AddressFamily, socket.SocketKind, int, str, tuple[str, int] | tuple[str, int, int, int]]

if TYPE_CHECKING:
    from pmk_nb.chair.link.transport.tls import ChairTls
    from pmk_nb.errors import ChairLinkError

REFUSED = "connection refused"
TIMED_OUT = "timed out"
HOST_UNKNOWN = "host unknown"
NOT_ROSBRIDGE = "not a rosbridge server"
TLS_FAILED = "TLS failed"
AUTH_FAILED = "authentication failed"
#: Added to a failed plain handshake: a wss-only bridge answers a ws client with TLS bytes.
TLS_HINT = "; if the chair's rosbridge serves TLS (wss), turn TLS on in the chair profile"


@dataclass(frozen=True)
class ProbeResult:
    """Outcome of :func:`probe_rosbridge`: ``reason`` starts with one of the module constants."""

    ok: bool
    reason: str
    ros_version: int | None = None
    timeout: float | None = None  # set when the reason is a timeout
    error: ChairLinkError | None = None  # a typed refusal (a TLS certificate not trusted), when there is one
    fingerprint: str | None = None  # wss: the chair's certificate, checked and trusted


def _resolve(host: str, port: int, timeout: float) -> list[AddrInfo] | str:
    """getaddrinfo with a deadline (the libc resolver can block far longer than we may wait)."""
    box: dict[str, object] = {}
    done = threading.Event()

    def work() -> None:
        try:
            box["infos"] = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
        except (OSError, ValueError) as err:  # gaierror; UnicodeError for a name part over 63 characters
            box["error"] = err
        finally:
            done.set()

    threading.Thread(target=work, name="pmk-link-dns", daemon=True).start()
    if not done.wait(max(timeout, 0.0)):
        return f"{TIMED_OUT}: resolving {host!r} took longer than {timeout:.1f} s"
    if isinstance(box.get("error"), ValueError):
        why = "a part between dots is empty or longer than 63 characters"
        return f"{HOST_UNKNOWN}: {host!r} is not a valid host name ({why}); check the chair's address"
    if "error" in box:
        return f"{HOST_UNKNOWN}: {host!r} cannot be resolved ({box['error']}); check the chair's address"
    return box["infos"]  # type: ignore[return-value]


def _tcp_connect(infos: list[AddrInfo], host: str, port: int, deadline: float) -> socket.socket | str:
    last = ""
    for family, socktype, proto, _name, addr in infos:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            break
        sock = socket.socket(family, socktype, proto)
        sock.settimeout(remaining)
        try:
            sock.connect(addr)
            return sock
        except ConnectionRefusedError:
            sock.close()
            last = f"{REFUSED}: nothing listens on {host}:{port} (is rosbridge running on the chair?)"
        except TimeoutError:
            sock.close()
            return f"{TIMED_OUT}: no TCP answer from {host}:{port} (firewall, wrong network or chair off?)"
        except OSError as err:
            sock.close()
            last = f"{REFUSED}: cannot reach {host}:{port} ({err.strerror or err})"
    return last or f"{TIMED_OUT}: no TCP answer from {host}:{port}"


def _rosbridge_check(ws, deadline: float, host: str, port: int, auth: BridgeAuth | None) -> ProbeResult:  # type: ignore[no-untyped-def]
    """Send one rosapi call (after the ``auth`` op, with ``auth``); any rosbridge answers ``call_service``
    (even for a missing service)."""
    if auth is not None:
        try:
            ws.send(json.dumps(auth.op(host, port)))
        except BridgeAuthError as err:
            return ProbeResult(False, f"{AUTH_FAILED}: {err}", error=err)
    ws.send(json.dumps({"op": "call_service", "id": "pmk-probe:get_time", "service": "/rosapi/get_time"}))
    start = time.monotonic()
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            waited = time.monotonic() - start
            return ProbeResult(
                False,
                f"{TIMED_OUT}: {host}:{port} opened a websocket but answered no rosbridge request within "
                f"{waited:.1f} s (a busy rosbridge, e.g. sending a big map, or not a rosbridge server)",
                timeout=waited,
            )
        try:
            raw = ws.recv(timeout=remaining)
        except TimeoutError:
            continue
        except ConnectionClosed as err:
            if auth is not None:  # rosbridge with authenticate:=true closes on a refused auth op
                refused = auth.refused(host, port)
                return ProbeResult(False, f"{AUTH_FAILED}: {refused}", error=refused)
            return ProbeResult(False, f"{NOT_ROSBRIDGE}: {host}:{port} closed the websocket ({err})")
        try:
            msg = json.loads(raw)
            op = msg.get("op")
        except (ValueError, AttributeError):
            return ProbeResult(False, f"{NOT_ROSBRIDGE}: {host}:{port} sent non-rosbridge data {str(raw)[:60]!r}")
        if op == "service_response" and msg.get("id") == "pmk-probe:get_time":
            values = msg.get("values") or {}
            version = None
            if msg.get("result", True) and isinstance(values, dict):
                stamp = values.get("time") or {}
                version = 2 if "sec" in stamp else 1 if "secs" in stamp else None
            return ProbeResult(True, "connected", version)
        if op in ("status", "publish", "service_response"):
            continue  # rosbridge chatter; keep waiting for our answer
        return ProbeResult(False, f"{NOT_ROSBRIDGE}: {host}:{port} answered with op {op!r}")


def _tls_wrap(
    sock: socket.socket, tls: ChairTls, host: str, port: int, deadline: float
) -> tuple[ssl.SSLSocket, str] | ProbeResult:
    """The TLS handshake and the certificate check, before any websocket byte; closes ``sock`` on failure."""
    try:
        sock.settimeout(max(deadline - time.monotonic(), 0.01))
        wrapped = tls.context().wrap_socket(sock, server_hostname=host)
    except ssl.SSLError as err:
        sock.close()
        refused = handshake_failure(tls, host, port, err)
        if refused is not None:
            return ProbeResult(False, f"{TLS_FAILED}: {refused}", error=refused)
        return ProbeResult(
            False,
            f"{TLS_FAILED}: {host}:{port} did not complete a TLS handshake ({err.reason or err}): does the chair's "
            "rosbridge serve TLS? (start it with its certfile and keyfile, or turn TLS off in the chair profile)",
        )
    except TimeoutError:
        sock.close()
        return ProbeResult(False, f"{TIMED_OUT}: {host}:{port} accepted TCP but never completed the TLS handshake")
    except OSError as err:
        sock.close()
        return ProbeResult(False, f"{TLS_FAILED}: {host}:{port} closed the connection during the TLS handshake ({err})")
    try:
        return wrapped, check_peer(tls, host, port, wrapped.getpeercert(binary_form=True))
    except ChairCertificateError as err:
        wrapped.close()
        return ProbeResult(False, f"{TLS_FAILED}: {err}", error=err)


def probe_rosbridge(
    host: str, port: int, timeout: float = 5.0, tls: ChairTls | None = None, *, auth: BridgeAuth | None = None
) -> ProbeResult:
    """Check step by step that ``ws://host:port`` (``wss://`` with ``tls``: the certificate checked
    first, see :mod:`.tls`) is a rosbridge server; never exceeds ``timeout``. ``auth``: rosbridge's
    ``auth`` op goes first (:mod:`.bridge_auth`); a chair that closes after it refused it."""
    deadline = time.monotonic() + timeout
    infos = _resolve(host, port, timeout)
    if isinstance(infos, str):
        return ProbeResult(False, infos)
    sock = _tcp_connect(infos, host, port, deadline)
    if isinstance(sock, str):
        return ProbeResult(False, sock)
    trusted = None
    if tls is not None:
        wrapped = _tls_wrap(sock, tls, host, port, deadline)
        if isinstance(wrapped, ProbeResult):
            return wrapped
        sock, trusted = wrapped
    remaining = deadline - time.monotonic()
    try:
        with ws_connect(
            f"ws://{f'[{host}]' if ':' in host else host}:{port}/",
            sock=sock,
            proxy=None,
            open_timeout=max(remaining, 0.01),
            close_timeout=0.5,
            ping_interval=None,
            compression=None,
        ) as ws:
            return dataclasses.replace(_rosbridge_check(ws, deadline, host, port, auth), fingerprint=trusted)
    except TimeoutError:
        return ProbeResult(
            False, f"{TIMED_OUT}: {host}:{port} accepted TCP but never completed the websocket handshake"
        )
    except InvalidStatus as err:
        return ProbeResult(
            False, f"{NOT_ROSBRIDGE}: {host}:{port} answered HTTP {err.response.status_code}, not a websocket"
        )
    except (InvalidHandshake, WebSocketException, OSError, EOFError) as err:
        if isinstance(err, OSError) and isinstance(err.__cause__, TimeoutError):
            return ProbeResult(False, f"{TIMED_OUT}: {host}:{port} did not complete the websocket handshake")
        hint = "" if tls is not None else TLS_HINT
        return ProbeResult(False, f"{NOT_ROSBRIDGE}: {host}:{port} failed the websocket handshake ({err}){hint}")
    finally:
        sock.close()
