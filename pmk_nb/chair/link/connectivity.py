"""The "Test connection" verb: connect, then read the published map's facts, never raising.

A failed connect is kept as a :class:`ConnectFailure` (the probe's reason, and the seconds when it
was a timeout) so the report shows the precise reason and :meth:`ChairLink.connect` raises a typed
error from the same facts; no one has to read the reason back out of an exception's text.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

from pmk_nb.chair.messages import MapInfo
from pmk_nb.errors import ChairLinkError, ChairTimeout

if TYPE_CHECKING:
    from pmk_nb.chair.link.client import ChairLink

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


@dataclass(frozen=True)
class ConnectFailure:
    """Why a connect failed: the reason in words; ``timeout`` is set when it ran out of time."""

    reason: str
    timeout: float | None = None

    def error(self, host: str, port: int) -> ChairLinkError:
        message = f"Cannot connect to the chair at {host}:{port}: {self.reason}"
        if self.timeout is not None:
            return ChairTimeout(message, operation=OPEN_WEBSOCKET, seconds=self.timeout, host=host, port=port)
        return ChairLinkError(message, host=host, port=port)


def run_connection_test(link: ChairLink, timeout: float) -> ConnectionReport:
    """Connect ``link`` and read the map metadata within ``timeout`` s; leaves it connected on success."""
    t0 = time.monotonic()
    deadline = t0 + timeout

    def report(ok: bool, reason: str, info: MapInfo | None = None) -> ConnectionReport:
        return ConnectionReport(ok, reason, info, link.ros_version, time.monotonic() - t0)

    failure = link.try_connect(timeout)
    if failure is not None:
        return report(False, failure.reason)
    try:
        info = link.map_info(max(0.1, deadline - time.monotonic()))
    except ChairLinkError:
        return report(False, f"connected but no map published within {timeout:.1f} s")
    return report(True, "connected", info)
