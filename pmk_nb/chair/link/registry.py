"""One link per chair per kernel: re-running a notebook cell must reuse the open connection.

This module-level registry is deliberate process state (the one exception to "no global mutable
state"): a Jupyter kernel re-executes cells, and each execution creating a fresh rosbridge
connection would leak sockets and threads and double the chair's rosbridge load. It is the only
place that holds links: the dashboard asks it through :func:`use_only` rather than keeping its own.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Collection
from typing import Any

from pmk_nb.chair.link.client import ChairLink

log = logging.getLogger(__name__)

_LINKS: dict[tuple[str, int], ChairLink] = {}
_LOCK = threading.Lock()


def get_link(host: str, port: int = 9090, **kw: Any) -> ChairLink:
    """The kernel's link to ``host:port``, created on first use (not connected yet).

    Stream settings in ``kw`` that differ from the existing link's are applied with
    :meth:`ChairLink.reconfigure`; another ``tls`` replaces the link; other constructor options
    only count on creation.
    """
    key = (host, int(port))
    with _LOCK:
        link = _LINKS.get(key)
        if link is not None and link.tls != kw.get("tls"):  # ws <-> wss or another trust: a new socket
            _LINKS.pop(key)
            link.close()
            link = None
        if link is None:
            link = ChairLink(host, int(port), **kw)
            _LINKS[key] = link
            return link
    current = link.config
    changes = {k: v for k, v in kw.items() if k in current and current[k] != v}
    if "throttle_ms" in changes and {**current["throttle_ms"], **changes["throttle_ms"]} == current["throttle_ms"]:
        del changes["throttle_ms"]
    if changes:
        link.reconfigure(**changes)
    return link


def use_only(host: str, port: int = 9090, *, keep: Collection[tuple[str, int]] = (), **kw: Any) -> ChairLink:
    """The link to ``host:port`` (as :func:`get_link`), after closing and dropping links to other chairs.

    A dashboard page talks to one chair: when its settings now name another one, the old connection
    must not linger. A failure to close an old link is logged, never raised (the new one matters).
    ``keep``: other chairs' ``(host, port)`` whose links stay open (the page's fleet, issue 26).
    """
    link = get_link(host, port, **kw)
    kept = {(h, int(p)) for h, p in keep}
    with _LOCK:
        others = [(key, old) for key, old in _LINKS.items() if old is not link and key not in kept]
        for key, _old in others:
            del _LINKS[key]
    for _key, old in others:
        try:
            old.close()
        except Exception as err:  # closing is best effort; the new link is what counts
            log.warning("closing the link to the previous chair %s:%s failed: %s", old.host, old.port, err)
    return link


def open_links() -> list[ChairLink]:
    with _LOCK:
        return list(_LINKS.values())


def forget_link(host: str, port: int = 9090) -> None:
    """Close and drop the link to ``host:port`` (no-op if there is none)."""
    with _LOCK:
        link = _LINKS.pop((host, int(port)), None)
    if link is not None:
        link.close()


def close_all_links() -> None:
    """Close every link of this kernel (e.g. before shutting the dashboard down)."""
    with _LOCK:
        links = list(_LINKS.values())
        _LINKS.clear()
    for link in links:
        link.close()
