"""One chair, one key: the drive claim and the Stop latch are keyed on where the chair is, not on how a
profile spells it (issue 38, item 4: profiles ``127.0.0.1`` and ``localhost`` for one chair gave two
drivers, and one page's Stop left the other turning).

The key is the chair's resolved address and port: every address ``socket.getaddrinfo`` gives for the
host, IPv4-mapped IPv6 read as IPv4; a host whose addresses are all loopback (``localhost``,
``127.0.0.1``, ``::1``, ``127.0.1.1``) is ``loopback``; otherwise the smallest address (IPv4 first), so
every spelling of a host with several addresses picks the same one. A host that does not resolve (no
DNS now) keeps its spelling, lower-cased and without a trailing dot or IPv6 brackets: it cannot be
told apart from another spelling then, and every page of this dashboard resolves the same way.
"""

from __future__ import annotations

import ipaddress
import re
import socket

LOOPBACK = "loopback"


def chair_address(host: str) -> str:
    """The chair's canonical address (see the module docstring)."""
    spelled = host.strip().strip("[]").rstrip(".").lower()
    try:
        infos = socket.getaddrinfo(spelled, None, type=socket.SOCK_STREAM)
    except (OSError, UnicodeError):
        return spelled
    addresses: set[ipaddress.IPv4Address | ipaddress.IPv6Address] = set()
    for info in infos:
        try:
            ip = ipaddress.ip_address(str(info[4][0]).split("%", 1)[0])
        except ValueError:
            continue
        if isinstance(ip, ipaddress.IPv6Address) and ip.ipv4_mapped is not None:
            ip = ip.ipv4_mapped
        addresses.add(ip)
    if not addresses:
        return spelled
    if all(ip.is_loopback for ip in addresses):
        return LOOPBACK
    return str(min(addresses, key=lambda ip: (ip.version, int(ip))))


def chair_key(host: str, port: int) -> str:
    """A file name for one chair: ``address_port`` with anything but letters, digits, ``.-`` as ``_``."""
    return re.sub(r"[^A-Za-z0-9.-]", "_", f"{chair_address(host)}_{int(port)}")[:120]
