"""One link per chair per kernel: re-running a notebook cell must reuse the open connection.

This module-level registry is deliberate process state (the one exception to "no global mutable
state"): a Jupyter kernel re-executes cells, and each execution creating a fresh rosbridge
connection would leak sockets and threads and double the chair's rosbridge load.
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from pmk_nb.chair.link.client import ChairLink

_LINKS: dict[tuple[str, int], ChairLink] = {}
_LOCK = threading.Lock()


def get_link(host: str, port: int = 9090, **kw: Any) -> ChairLink:
    """The kernel's link to ``host:port``, created on first use (not connected yet).

    Stream settings in ``kw`` that differ from the existing link's are applied with
    :meth:`ChairLink.reconfigure`; other constructor options only count on creation.
    """
    from pmk_nb.chair.link.client import ChairLink  # lazy: link.py re-exports this module's functions

    key = (host, int(port))
    with _LOCK:
        link = _LINKS.get(key)
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
