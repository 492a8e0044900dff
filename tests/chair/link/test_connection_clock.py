"""The connection test's deadline on virtual time (issue 39): the map read gets what the connect left
of the timeout, and the report's elapsed time is the clock's, exactly."""

from __future__ import annotations

from typing import Any

from pmk_nb.chair.link.query.connectivity import run_connection_test
from pmk_nb.clock import VirtualClock
from pmk_nb.errors import ChairLinkError


class SlowChair:
    """Connects in 1.5 s; its map read uses 2 s of what it was given, then finds no map."""

    ros_version, rosapi_timeout, host, port = 2, 3.0, "127.0.0.1", 9090

    def __init__(self, clock: VirtualClock) -> None:
        self.clock = clock
        self.ros: Any = type("Ros", (), {"protocol": object()})()
        self.discovery: Any = type("Discovery", (), {"rosapi": True})()
        self.map_timeouts: list[float] = []

    def try_connect(self, timeout: float) -> None:
        self.clock.advance(1.5)

    def map_info(self, timeout: float) -> Any:
        self.map_timeouts.append(timeout)
        self.clock.advance(2.0)
        raise ChairLinkError("no map", host=self.host, port=self.port)


def test_the_map_read_gets_the_rest_of_the_timeout_and_elapsed_is_exact() -> None:
    clock = VirtualClock(start=0.0)
    chair = SlowChair(clock)
    report = run_connection_test(chair, 5.0, lambda: False, clock=clock)  # type: ignore[arg-type]
    assert chair.map_timeouts == [3.5]
    assert not report.ok and report.reason == "connected but no map published within 5.0 s"
    assert report.elapsed == 3.5
