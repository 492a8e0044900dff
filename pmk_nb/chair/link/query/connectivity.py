"""The "Test connection" verb: connect, then read the published map's facts, never raising.

A failed connect is kept as a :class:`ConnectFailure` (the probe's reason, and the seconds when it
was a timeout) so the report shows the precise reason and :meth:`ChairLink.connect` raises a typed
error from the same facts; no one has to read the reason back out of an exception's text.

A bridge without rosapi is a working connection: the report is ``ok`` with ``rosapi=False`` and a
note in plain words (what does not work without it, and that the map reload will try the known
service names), never the bridge's raw error.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from pmk_nb.chair.link.goals import goal_words
from pmk_nb.chair.link.query.bridge_kind import BridgeKind, detect_bridge
from pmk_nb.chair.link.query.reload import PREFERRED
from pmk_nb.chair.link.streams.messages import MapInfo
from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.errors import ChairLinkError, ChairTimeout

if TYPE_CHECKING:
    from pmk_nb.chair.link.core import LinkCore

#: What the websocket open waits for, as :attr:`ChairTimeout.operation`.
OPEN_WEBSOCKET = "open the rosbridge websocket"


@dataclass(frozen=True)
class ConnectionReport:
    """What "Test connection" shows: ok + map facts, or the precise reason it failed."""

    ok: bool
    reason: str
    map_info: MapInfo | None
    ros_version: int | None
    elapsed: float
    rosapi: bool | None = None  # False: the bridge has no rosapi (topics cannot be listed)
    notes: tuple[str, ...] = ()  # plain-word remarks for a successful test (no rosapi, ...)
    error: ChairLinkError | None = None  # a typed refusal behind ``reason`` (an untrusted TLS certificate)
    bridge: BridgeKind | None = None  # ROS 2: which rosbridge server (how it treats goals)


def big_map_stuck(timeout: float) -> str:
    """The chair publishes a map, but it did not cross the bridge: say why it usually is."""
    return (
        f"connected; the chair publishes a map but it did not arrive within {timeout:.1f} s: a big map may not "
        "fit the rosbridge server's send queue (rosbridge-server-rs: raise --write-queue-bytes), or run the PMK "
        "map server, whose map_info service gives the map's size without sending the grid"
    )


def no_rosapi_note() -> str:
    """What a user needs to know about a bridge without rosapi."""
    names = ", ".join(name for name, _kind in PREFERRED)
    return (
        "The rosbridge server runs without rosapi, so the chair's topics cannot be listed: type the "
        f"topic names yourself. Sending a map still works: the known reload services ({names}) are tried by name."
    )


@dataclass(frozen=True)
class ConnectFailure:
    """Why a connect failed: the reason in words; ``timeout`` is set when it ran out of time."""

    reason: str
    timeout: float | None = None
    refusal: ChairLinkError | None = None  # typed (a TLS certificate not trusted): raised as it is

    def error(self, host: str, port: int) -> ChairLinkError:
        if self.refusal is not None:
            return self.refusal
        message = f"Cannot connect to the chair at {host}:{port}: {self.reason}"
        if self.timeout is not None:
            return ChairTimeout(message, operation=OPEN_WEBSOCKET, seconds=self.timeout, host=host, port=port)
        return ChairLinkError(message, host=host, port=port)


def run_connection_test(
    link: LinkCore, timeout: float, map_listed: Callable[[], bool], *, clock: Clock = MONOTONIC
) -> ConnectionReport:
    """Connect ``link`` and read the map metadata within ``timeout`` s of ``clock``; leaves it connected
    on success. ``map_listed``: did the map read find the map topic listed (the link's map reader says)."""
    t0 = clock.now()
    deadline = t0 + timeout

    def report(
        ok: bool,
        reason: str,
        info: MapInfo | None = None,
        bridge: BridgeKind | None = None,
        error: ChairLinkError | None = None,
    ) -> ConnectionReport:
        rosapi = link.discovery.rosapi
        notes: tuple[str, ...] = (no_rosapi_note(),) if rosapi is False else ()
        if bridge is not None and bridge.keeps_lost_goals:
            notes += (goal_words.bridge_ignores_cancels(bridge.goals_in_new_thread),)
        elapsed = clock.now() - t0
        return ConnectionReport(ok, reason, info, link.ros_version, elapsed, rosapi, notes, error, bridge)

    failure = link.try_connect(timeout)
    if failure is not None:
        return report(False, failure.reason, error=failure.refusal)
    socket = getattr(link.ros, "protocol", None)
    try:
        info = link.map_info(max(0.1, deadline - clock.now()))
    except ChairLinkError:
        if getattr(link.ros, "protocol", None) is not socket or map_listed():  # closed us, or dropped it
            return report(False, big_map_stuck(timeout))
        return report(False, f"connected but no map published within {timeout:.1f} s")
    if link.discovery.rosapi is None:  # the map's facts came without rosapi: ask once
        try:
            link.discovery.topics(max(0.1, min(link.rosapi_timeout, deadline - clock.now())))
        except ChairLinkError:
            pass  # RosapiMissing is remembered; a busy bridge stays "unknown"
    bridge = None
    if link.ros_version == 2 and link.discovery.rosapi is not False:
        bridge = detect_bridge(link, max(0.1, min(link.rosapi_timeout, deadline - clock.now())))
    return report(True, "connected", info, bridge)
