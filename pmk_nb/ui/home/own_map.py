"""Home's view of the chair's own map: whatever the chair publishes on ``/map`` is what Home shows.

A map made by SLAM, sent by ``pmk send`` or from another tablet is the chair's map as much as one
sent from this page. While the preview runs, :class:`OwnMap` keeps the link's map watch on
(:meth:`pmk_nb.chair.link.client.ChairLink.watch_map`: latched ``/map``, stored on the I/O thread)
and, on a worker thread of its own (never the link's I/O thread, never the kernel's event loop: a
big grid takes a while), turns each new map into a grid and names it: the current map's name when
the chair's grid is that map (the maps folder's record of what was sent), else "the chair's map".
Home takes the result at its next info refresh (:meth:`OwnMap.take`) and shows it.

Big maps: when the chair runs the PMK map server, its MapInfo service (header and SHA-256, no grid)
is asked first; while it says the chair publishes the map sent from here, that map's own file is
shown and the chair's (possibly 16-million-cell) ``/map`` is never downloaded.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pmk_nb.errors import PmkError

if TYPE_CHECKING:
    from pmk_nb.chair.link import MapWatchLink
    from pmk_nb.grid import OccupancyGrid

log = logging.getLogger(__name__)

FACTS_S = 2.0  # how often MapInfo is asked while it says the sent map is the chair's
POLL_S = 0.25  # how often the worker looks for a new map (the callback only stores it)
SAME_CELLS = 0.98  # share of equal cells for "the map sent": a chair's image reader rounds some cells
CHAIRS_MAP = "the chair's map"


@dataclass(frozen=True)
class ChairMap:
    """A map the chair published: its grid, the name to show, and whether it is the map sent."""

    grid: OccupancyGrid
    name: str
    is_sent_map: bool


def same_map(ours: OccupancyGrid | None, theirs: OccupancyGrid) -> bool:
    """Is the chair's grid the map we have (same size, resolution, origin; nearly every cell)?"""
    if ours is None or ours.data.shape != theirs.data.shape:
        return False
    if abs(ours.resolution - theirs.resolution) > 1e-6 * ours.resolution:
        return False
    if any(abs(a - b) > ours.resolution / 2 for a, b in zip(ours.origin[:2], theirs.origin[:2], strict=True)):
        return False
    return bool(np.count_nonzero(ours.data == theirs.data) >= SAME_CELLS * ours.data.size)


class OwnMap:
    """Watches one link's ``/map`` while attached; the newest map waits in :meth:`take`."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._link: MapWatchLink | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._local: tuple[str, OccupancyGrid] | None = None
        self._local_yaml: Path | None = None
        self._pending: ChairMap | None = None
        #: the map shown now (None: none received from this link yet)
        self.current: ChairMap | None = None
        self.problem: str | None = None  # why the watch or the last map failed, in words

    def set_local(self, name: str | None, grid: OccupancyGrid | None, yaml: Path | None = None) -> None:
        """The current map from the maps folder (the last one sent), to name the chair's map; its
        ``yaml`` lets the PMK map server's MapInfo spare the /map download (see :meth:`_sent_map_in_use`)."""
        with self._lock:
            self._local = (name, grid) if name is not None and grid is not None else None
            self._local_yaml = Path(yaml) if self._local is not None and yaml is not None else None
            shown = self.current
        if shown is not None:  # the record changed: the same grid may have a name now
            self._offer(shown.grid)

    def attach(self, link: MapWatchLink | None) -> None:
        """Watch ``link``'s map (None: stop watching and forget the chair's map)."""
        with self._lock:
            old, self._link = self._link, link
            thread, self._thread = self._thread, None
            self._stop.set()
            self._stop = threading.Event()
            self.current, self._pending, self.problem = None, None, None
        if thread is not None:
            thread.join(timeout=2 * POLL_S)
        if old is not None and old is not link:
            threading.Thread(target=_unwatch, args=(old,), daemon=True, name="pmk-own-map-stop").start()
        if link is not None:  # started before it is published: another attach may join it at once
            started = threading.Thread(target=self._run, args=(link, self._stop), daemon=True, name="pmk-own-map")
            started.start()
            self._thread = started

    def take(self) -> ChairMap | None:
        """The map to show now if it is new since the last call, else None (Home's info refresh)."""
        with self._lock:
            pending, self._pending = self._pending, None
            if pending is not None:
                self.current = pending
            return pending

    # -- worker ----------------------------------------------------------------------------------
    def _run(self, link: MapWatchLink, stop: threading.Event) -> None:
        seen = 0
        facts = _FactsCheck()
        while not stop.wait(POLL_S):
            try:
                if link.is_connected and not link.watching_map:
                    if self._sent_map_in_use(link, facts):
                        continue
                    link.watch_map(True)
                count, grid = link.latest_map()
            except (PmkError, OSError) as err:
                self.problem = f"the chair's map cannot be read: {err}"
                continue
            if count == seen:
                continue
            seen = count
            if grid is None:
                self.problem = link.map_problem
                continue
            self.problem = None
            if not stop.is_set():
                self._offer(grid)

    def _sent_map_in_use(self, link: MapWatchLink, check: _FactsCheck) -> bool:
        """True while the PMK map server's MapInfo says the chair publishes the map sent from here
        (the same SHA-256): the local grid is shown and a (possibly huge) /map is not downloaded.
        Asked every :data:`FACTS_S` s; a chair without that service, or another map: False for good
        (the /map watch takes over and follows every later map)."""
        with self._lock:
            local, yaml = self._local, self._local_yaml
        if local is None or yaml is None or check.unavailable:
            return False
        now = time.monotonic()
        if now - check.asked < FACTS_S:
            return check.in_use
        check.asked = now
        try:
            facts = link.map_facts(FACTS_S)
            if facts is not None and (check.sha is None or check.sha[0] != yaml):
                check.sha = (yaml, _file_sha256(yaml))
        except (PmkError, OSError, ValueError) as err:  # a busy bridge, an unreadable file: use /map
            log.info("MapInfo check failed, watching /map instead: %s", err)
            facts = None
        if facts is None or check.sha is None:
            check.unavailable = True
            return False
        check.in_use = facts.loaded and facts.sha256 == check.sha[1]
        if check.in_use and facts.stamp != check.stamp:
            check.stamp = facts.stamp
            self._offer(local[1])
        if not check.in_use:
            check.unavailable = True  # another map: from now on the /map watch
        return check.in_use

    def _offer(self, grid: OccupancyGrid) -> None:
        with self._lock:
            local = self._local
        sent = local is not None and same_map(local[1], grid)
        name = local[0] if sent and local is not None else CHAIRS_MAP
        with self._lock:
            self._pending = ChairMap(grid, name, sent)


@dataclass
class _FactsCheck:
    """One worker's MapInfo checks (see :meth:`OwnMap._sent_map_in_use`)."""

    asked: float = -math.inf
    unavailable: bool = False
    in_use: bool = False
    stamp: float | None = None
    sha: tuple[Path, str] | None = None


def _file_sha256(yaml: Path) -> str:
    """SHA-256 of a map file's cells as the PMK map server computes it (the deploy check's helper)."""
    from pmk_nb.chair import map_sha256
    from pmk_nb.rosmap import MapFiles, read_map_yaml

    return map_sha256(MapFiles(yaml, Path(read_map_yaml(yaml).image), None))


def _unwatch(link: MapWatchLink) -> None:
    try:
        link.watch_map(False)
    except Exception as err:  # the link may be closed already
        log.info("stopping the map watch failed: %s", err)


def map_label_html(name: str, is_sent_map: bool) -> str:
    """Home's title line for the map shown: the sent map's name, or the chair's own map."""
    from pmk_nb.ui.common.widgets import escape

    if is_sent_map:
        return f"Current map: <b>{escape(name)}</b>"
    return (
        f"Current map: <b class='pmk-home-chair-map'>{escape(name)}</b> "
        "<small>(published by the chair; your maps are on the <b>Maps</b> screen)</small>"
    )
