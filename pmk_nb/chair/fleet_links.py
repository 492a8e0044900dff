"""The fleet's links (issue 26): one :class:`ChairLink` per chair, each connected and watched on its
own worker thread, so a chair that does not answer never holds up the others.

Links come from the kernel's registry (:func:`~pmk_nb.chair.link.registry.get_link`): the chair in
control is the very link Home, Drive and Go to use, and handing control to another chair only
re-points them at a link that is already open (no reconnect).  A chair that is only watched
streams what its row and marker need: odometry and pose at most :data:`BACKGROUND_THROTTLE_MS`
apart, the laser barely (rosbridge throttles it on the chair's side); the chair in control gets the
full streams back.  Every :data:`FACTS_EVERY_S` the worker asks the PMK map server which map the
chair uses (a chair without one says "map not known").
"""

from __future__ import annotations

import functools
import logging
import threading
import time
from dataclasses import dataclass, field
from pathlib import PurePosixPath
from typing import TYPE_CHECKING

from pmk_nb.chair.fleet import ChairStatus, FleetMember
from pmk_nb.chair.link.registry import forget_link, get_link
from pmk_nb.chair.link.streams.hub import DEFAULT_THROTTLE_MS
from pmk_nb.chair.link.transport.state import LinkState
from pmk_nb.errors import PmkError

if TYPE_CHECKING:
    from pmk_nb.chair.link.client import ChairLink

log = logging.getLogger(__name__)

#: A watched chair's streams (ms between messages rosbridge forwards): a marker moves 5 times a
#: second, the laser (drawn only for the chair in control) comes once in 5 s.
BACKGROUND_THROTTLE_MS: dict[str, int] = {"odom": 200, "scan": 5000, "pose": 200, "tf": 0}
FACTS_EVERY_S = 5.0  # how often a watched chair is asked which map it uses
RETRY_EVERY_S = 5.0  # a chair that did not answer is tried again this often
CONNECT_TIMEOUT_S = 5.0


@dataclass
class _Watch:
    """One chair's worker and what it learned (written by the worker, read by the panel's timer)."""

    member: FleetMember
    stop: threading.Event = field(default_factory=threading.Event)
    link: ChairLink | None = None
    error: PmkError | None = None
    map_name: str | None = None
    map_key: object = None  # what tells two maps apart: MapInfo's SHA-256, else size, resolution, origin
    thread: threading.Thread | None = None


class FleetLinks:
    """Opens, watches and closes the fleet's links; thread-safe.

    Args:
        connect_timeout, facts_every, retry_every: seconds (tests shorten them).
    """

    def __init__(
        self,
        *,
        connect_timeout: float = CONNECT_TIMEOUT_S,
        facts_every: float = FACTS_EVERY_S,
        retry_every: float = RETRY_EVERY_S,
    ) -> None:
        self.connect_timeout, self.facts_every, self.retry_every = connect_timeout, facts_every, retry_every
        self._lock = threading.RLock()
        self._watches: dict[str, _Watch] = {}
        self._controlled: str | None = None

    # -- members -----------------------------------------------------------------------------------
    def open(self, member: FleetMember) -> None:
        """Start watching ``member`` (connecting on its own thread); a second call changes nothing."""
        with self._lock:
            if member.name in self._watches:
                return
            watch = _Watch(member)
            self._watches[member.name] = watch
        watch.thread = threading.Thread(
            target=self._run, args=(watch,), name=f"pmk-fleet-{member.key[0]}:{member.key[1]}", daemon=True
        )
        watch.thread.start()

    def close(self, name: str, *, keep_link: bool = False) -> None:
        """Stop watching ``name`` and close its link (``keep_link``: the page's own chair stays open)."""
        with self._lock:
            watch = self._watches.pop(name, None)
            if self._controlled == name:
                self._controlled = None
        if watch is None:
            return
        watch.stop.set()
        if not keep_link:
            try:
                forget_link(*watch.member.key)
            except Exception as err:  # closing is best effort
                log.warning("closing the fleet's link to %s failed: %s", watch.member.name, err)

    def close_all(self, keep: tuple[str, int] | None = None) -> None:
        """Close every link of the fleet except the one to ``keep`` (the chair Home still shows)."""
        with self._lock:
            names = [(n, w.member.key) for n, w in self._watches.items()]
        for name, key in names:
            self.close(name, keep_link=key == keep)

    def map_key(self, name: str) -> object:
        """What identifies the map ``name`` uses (None: not known yet)."""
        with self._lock:
            watch = self._watches.get(name)
        return watch.map_key if watch is not None else None

    def link(self, name: str) -> ChairLink | None:
        with self._lock:
            watch = self._watches.get(name)
        return watch.link if watch is not None else None

    # -- control -----------------------------------------------------------------------------------
    def set_controlled(self, name: str | None) -> None:
        """``name``'s link gets the full streams (Home starts them); the previous one goes back to
        the watched chairs' light streams. No link is reconnected."""
        with self._lock:
            previous, self._controlled = self._controlled, name
            before = self._watches.get(previous) if previous is not None and previous != name else None
            now = self._watches.get(name) if name is not None else None
        if before is not None and before.link is not None:
            self._light(before.link)
        if now is not None and now.link is not None:
            now.link.reconfigure(throttle_ms=dict(DEFAULT_THROTTLE_MS))

    @staticmethod
    def _light(link: ChairLink) -> None:
        link.reconfigure(throttle_ms=dict(BACKGROUND_THROTTLE_MS))
        link.start_streams()

    # -- reading -----------------------------------------------------------------------------------
    def status(self, member: FleetMember, goal: str | None = None, shown_map: object = None) -> ChairStatus:
        """``member``'s row now: never blocks (the worker did the asking). ``shown_map``: the
        :meth:`map_key` of the map the page shows (a chair on another map is not drawn on it)."""
        with self._lock:
            watch = self._watches.get(member.name)
            controlled = self._controlled == member.name
        row = functools.partial(ChairStatus, name=member.name, colour=member.colour, controlled=controlled, goal=goal)
        if watch is None:
            return row(connection="off")
        link, error, map_name, key = watch.link, watch.error, watch.map_name, watch.map_key
        same = shown_map is None or key is None or key == shown_map
        if link is None or (error is not None and not link.is_connected):
            problem = str(error) if error is not None else None
            return row(connection="unreachable" if error else "connecting", problem=problem)
        state = link.state
        connection = {LinkState.CONNECTED: "live", LinkState.STALE: "stale"}.get(state, "connecting")
        pose = link.latest_pose() or link.latest_odom()
        xyt = (float(pose.x), float(pose.y), float(pose.theta)) if pose is not None else None
        return row(connection=connection, map_name=map_name, pose=xyt, same_map=same)

    # -- worker ------------------------------------------------------------------------------------
    def _run(self, watch: _Watch) -> None:
        """Connect (again every ``retry_every`` s while the chair does not answer), then ask for its map."""
        member, stop = watch.member, watch.stop
        next_facts = 0.0
        while not stop.is_set():
            try:
                if watch.link is None or watch.link.ros is None:  # never connected (or closed): connect;
                    self._connect(watch)  # a link that dropped reconnects by itself, with its backoff
                if time.monotonic() >= next_facts:
                    watch.map_name, watch.map_key = _map_identity(watch.link)
                    next_facts = time.monotonic() + self.facts_every
            except PmkError as err:  # the row says so; the other chairs go on
                watch.error = err
                stop.wait(self.retry_every)
                continue
            except Exception as err:  # a bug must not end the watch silently
                log.exception("watching %s failed", member.name)
                watch.error = PmkError(f"watching {member.name} failed: {err}")
                stop.wait(self.retry_every)
                continue
            stop.wait(min(1.0, self.facts_every))  # a link closed meanwhile is found within a second

    def _connect(self, watch: _Watch) -> None:
        host, port = watch.member.key
        link = get_link(host, port, **watch.member.profile.link_options())
        watch.link = link
        link.connect(timeout=self.connect_timeout)
        watch.error = None
        with self._lock:
            controlled = self._controlled == watch.member.name
        if not controlled and not watch.stop.is_set():
            self._light(link)


def _map_identity(link: ChairLink | None) -> tuple[str | None, object]:
    """(name, key) of the chair's map: the PMK map server's YAML name and SHA-256; without one, its
    size from ``/map_metadata`` (never the grid itself); (None, None) when the chair does not say."""
    if link is None:
        return None, None
    try:
        facts = link.map_facts(timeout=3.0)
        if facts is not None and facts.loaded and facts.path:
            return PurePosixPath(facts.path).stem, facts.sha256
        info = link.map_info(timeout=3.0, without_grid=True)
    except PmkError:
        return None, None
    res = float(info.resolution)
    name = f"{info.width * res:.1f} × {info.height * res:.1f} m map"
    key = (int(info.width), int(info.height), round(res, 6), tuple(round(float(v), 3) for v in info.origin))
    return name, key
