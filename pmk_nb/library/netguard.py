"""Downloads reach only public addresses unless a lab allows local ones (issue 30: SSRF).

A kiosk page could ask the dashboard to download ``http://127.0.0.1:PORT/`` or a LAN address and
show what answered (the chair's rosbridge, a router's page). The guard resolves the host name,
refuses it when ANY of its addresses is not public, and then connects to one of the addresses it
checked, never to the name again: a DNS answer that changes between the check and the connection
(rebinding) cannot slip a local address in. The same guard sits in every connection of the opener,
so each redirect's target is checked before it is connected to.

Proxies from the environment are not used: through a proxy the address that answers is the
proxy's choice, which no check here could see.
"""

from __future__ import annotations

import functools
import http.client
import ipaddress
import socket
import urllib.request
from typing import Any

from pmk_nb.errors import AddressRefused

#: Set to "1" by ``pmk dashboard --allow-local`` so the kernel's Maps screen may download from a lab server.
ALLOW_LOCAL_ENV = "PMK_ALLOW_LOCAL_DOWNLOADS"
_CGNAT = ipaddress.ip_network("100.64.0.0/10")
_NAT64 = ipaddress.ip_network("64:ff9b::/96")
_Address = ipaddress.IPv4Address | ipaddress.IPv6Address


def refusal(address: str) -> str | None:
    """Why ``address`` (an IP literal, maybe with an IPv6 ``%scope``) is not public, or None if it is."""
    try:
        ip: _Address = ipaddress.ip_address(address.split("%", 1)[0])
    except ValueError:
        return "not an IP address"
    if isinstance(ip, ipaddress.IPv6Address):
        embedded = (  # IPv6 forms that reach an IPv4 address: judged by that address
            ("IPv4-mapped", ip.ipv4_mapped),
            ("6to4", ip.sixtofour),
            ("NAT64", ipaddress.IPv4Address(int(ip) & 0xFFFFFFFF) if ip in _NAT64 else None),
        )
        for form, inner_ip in embedded:
            if inner_ip is not None:
                inner = refusal(str(inner_ip))
                return f"{form} {inner}" if inner else None
    checks = (
        (ip.is_unspecified, "unspecified address"),
        (ip.is_loopback, "loopback address"),
        (ip.is_link_local, "link-local address"),
        (ip.is_multicast, "multicast address"),
        (ip in _CGNAT, "shared (carrier-grade NAT) address"),
        (ip.is_reserved, "reserved address"),
        (ip.is_private, "private (LAN) address"),
        (not ip.is_global, "non-public address"),
    )
    return next((why for bad, why in checks if bad), None)


def open_checked(
    address: tuple[str, int],
    timeout: float | None,
    source_address: tuple[str, int] | None = None,
    *,
    url: str,
    allow_local: bool,
) -> socket.socket:
    """``socket.create_connection`` that connects only to addresses it checked (see the module doc)."""
    host, port = address
    infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)  # a gaierror is urllib's to report
    if not allow_local:
        for info in infos:
            address_text = str(info[4][0])  # an IP address (the stubs allow an int for other families)
            why = refusal(address_text)
            if why is not None:
                raise AddressRefused(url=url, host=host, address=address_text, reason=why)
    last: OSError | None = None
    for family, kind, proto, _name, sockaddr in infos:
        sock = socket.socket(family, kind, proto)
        try:
            if timeout is not socket._GLOBAL_DEFAULT_TIMEOUT:  # type: ignore[attr-defined]
                sock.settimeout(timeout)
            if source_address:
                sock.bind(source_address)
            connect(sock, sockaddr)
            return sock
        except OSError as err:
            sock.close()
            last = err
    raise last if last is not None else OSError(f"no address for {host}")


def connect(sock: socket.socket, sockaddr: Any) -> None:
    """Connect ``sock`` to the checked ``sockaddr`` (a seam: tests route a fake public address to loopback)."""
    sock.connect(sockaddr)


class _Guarded:
    """Mixed into http.client's connections: their socket comes from :func:`open_checked`."""

    def __init__(self, *args: Any, url: str, allow_local: bool, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._create_connection = functools.partial(open_checked, url=url, allow_local=allow_local)


class _GuardedHTTP(_Guarded, http.client.HTTPConnection):
    pass


class _GuardedHTTPS(_Guarded, http.client.HTTPSConnection):
    pass


class _HTTPHandler(urllib.request.HTTPHandler):
    def __init__(self, allow_local: bool) -> None:
        super().__init__()
        self.allow_local = allow_local

    def http_open(self, req: urllib.request.Request) -> http.client.HTTPResponse:
        conn = functools.partial(_GuardedHTTP, url=req.full_url, allow_local=self.allow_local)
        return self.do_open(conn, req)


class _HTTPSHandler(urllib.request.HTTPSHandler):
    def __init__(self, allow_local: bool) -> None:
        super().__init__()
        self.allow_local = allow_local

    def https_open(self, req: urllib.request.Request) -> http.client.HTTPResponse:
        conn = functools.partial(_GuardedHTTPS, url=req.full_url, allow_local=self.allow_local)
        # urllib keeps the handler's TLS settings private (the stubs leave them out)
        return self.do_open(conn, req, context=self._context, check_hostname=self._check_hostname)  # type: ignore[attr-defined]


def guarded_handlers(allow_local: bool) -> list[urllib.request.BaseHandler]:
    """Handlers for ``build_opener``: no proxies, every connection (redirects too) checked."""
    return [urllib.request.ProxyHandler({}), _HTTPHandler(allow_local), _HTTPSHandler(allow_local)]
