"""The link's reconnect backoff and websocket pings, the same on both roslibpy transports.

Kept apart from :mod:`pmk_nb.chair.link.transport.factory` (asyncio) and
:mod:`pmk_nb.chair.link.transport.factory_twisted`: importing either one binds Autobahn to its framework, so
neither may import the other.
"""

from __future__ import annotations

from typing import Any

FACTOR = 2.0  # each reconnect waits twice as long, up to the link's max_delay
JITTER = 0.1


def set_backoff(factory: Any, initial_delay: float, max_delay: float) -> None:
    """Instance attributes shadow roslibpy's class-wide defaults (1 s x 2.7 up to an hour), which would
    leave a chair that rebooted disconnected for minutes; setting them on the class would change
    every other client too."""
    factory.initialDelay = initial_delay
    factory.maxDelay = max_delay
    factory.factor = FACTOR
    factory.jitter = JITTER


def set_pings(factory: Any, ping_interval: float, ping_timeout: float) -> None:
    """Websocket pings notice half-open sockets (chair left the Wi-Fi) that TCP would keep "open" for
    many minutes; rosbridge itself never tells. Each ping must get its pong: autobahn's "any traffic
    counts" mode logs a warning for every late pong while streaming."""
    factory.setProtocolOptions(
        closeHandshakeTimeout=1,
        openHandshakeTimeout=max(2.0, ping_timeout),
        autoPingInterval=ping_interval,
        autoPingTimeout=ping_timeout,
        autoPingRestartOnAnyTraffic=False,
    )
