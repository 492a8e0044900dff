"""The rosbridge link to one chair (roslibpy): connection test, streams, discovery, map, services.

``client`` holds :class:`ChairLink`, the chair-level verbs; underneath, ``transport`` (roslibpy on a
private asyncio loop), ``probe`` (is it a rosbridge server?), ``streams`` (odometry, scan, pose, tf;
callbacks only store), ``discovery`` (rosapi), ``mapread`` (the published map), ``state`` and
``registry`` (one link per chair per kernel).
"""

from __future__ import annotations

from pmk_nb.chair.link.client import ChairLink, ConnectionReport
from pmk_nb.chair.link.registry import close_all_links, forget_link, get_link, open_links
from pmk_nb.chair.link.state import LinkState

__all__ = [
    "ChairLink",
    "ConnectionReport",
    "LinkState",
    "close_all_links",
    "forget_link",
    "get_link",
    "open_links",
]
