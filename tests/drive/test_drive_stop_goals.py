"""Issue 38: Stop cancels goals on every page, and one chair has one key whatever its spelling.

Item 1 as the attacker did it: page A's "Go to" runs a goal; page B presses Stop. B's session cancels
its own goals and all goals natively; A's kernel sees the latch (its StopWatch) and cancels A's goal;
A cannot send another until B releases. Item 4: B's profile says ``localhost`` where A's says
``127.0.0.1``: the claim and the latch are the same file, so B's Stop stops A and one drives at a time.
"""

from __future__ import annotations

import math
import socket
from pathlib import Path

import pytest

from pmk_nb.chair.link import GoalsStopped, GoalStatus
from pmk_nb.clock import VirtualClock
from pmk_nb.drive import DriveClaim, DriveSession, Hold, StopWatch
from pmk_nb.drive.chairkey import LOOPBACK, chair_address, chair_key
from pmk_nb.drive.stopwatch import POLL_S
from tests.fixtures_sim import wait_until

START = (1.0, 6.0, 0.0)
FAR = (14.0, 6.0, 0.0)


def test_every_spelling_of_one_chair_is_one_key() -> None:
    spellings = ["127.0.0.1", "localhost", "LOCALHOST.", " localhost ", "::1", "[::1]", "127.0.1.1"]
    assert {chair_key(h, 9090) for h in spellings} == {f"{LOOPBACK}_9090"}
    assert chair_key("localhost", 9091) != chair_key("127.0.0.1", 9090)  # another port: another chair
    assert chair_address("::ffff:192.0.2.7") == "192.0.2.7"  # IPv4-mapped IPv6 is the IPv4 address
    assert chair_address("192.0.2.7") == "192.0.2.7" != chair_address("192.0.2.8")


def test_unresolvable_names_keep_their_own_key(monkeypatch: pytest.MonkeyPatch) -> None:
    def fail(*_a: object, **_k: object) -> list:
        raise socket.gaierror("no DNS")

    monkeypatch.setattr(socket, "getaddrinfo", fail)
    assert chair_key("chair-7.lan", 9090) == "chair-7.lan_9090"
    assert chair_address("Chair-7.LAN.") == "chair-7.lan"  # its spelling, normalised


def test_two_spellings_share_the_driver_claim_and_the_stop(tmp_path: Path) -> None:
    a = DriveClaim(tmp_path, "127.0.0.1", 9090, member="a")
    b = DriveClaim(tmp_path, "localhost", 9090, member="b")
    assert a.path == b.path
    assert a.acquire().hold is Hold.MINE
    assert b.acquire().hold is Hold.OTHER_DRIVER  # two drivers before issue 38
    b.stop()
    assert a.view().hold is Hold.STOPPED_ELSEWHERE


class FakeLink:
    is_connected = True

    def __init__(self) -> None:
        self.stops: list[str | None] = []

    def latest_odom(self) -> None:
        return None

    def publish_cmd_vel(self, v: float, w: float, topic: str | None = None) -> bool:
        return True

    def stop_goals(self, topic: str | None = None) -> list:
        self.stops.append(topic)
        return []


def test_stop_cancels_goals_and_the_watch_of_another_page_answers_once(tmp_path: Path) -> None:
    link = FakeLink()
    session = DriveSession(link, topic="/chair/cmd_vel", claim=DriveClaim(tmp_path, "localhost", 9090, member="b"))
    fired: list[int] = []
    watch_a = StopWatch(DriveClaim(tmp_path, "127.0.0.1", 9090, member="a"), lambda: fired.append(1))
    watch_b = StopWatch(DriveClaim(tmp_path, "127.0.0.1", 9090, member="b"), lambda: fired.append(2))
    watch_a.tick(), watch_b.tick()
    assert watch_a.latched_at() is None and not fired and not watch_a.latched
    session.stop()
    assert link.stops == ["/chair/cmd_vel"]  # the pressing page cancels at once, on its velocity topic
    watch_a.tick(), watch_b.tick(), watch_a.tick()
    assert fired == [1]  # A answers B's latch once; B's own watch leaves it to B's Stop
    assert watch_a.latched and watch_a.latched_at() == session.claim_view.stop_at  # type: ignore[union-attr]
    session.release_stop()
    watch_a.tick()
    assert watch_a.latched_at() is None and not watch_a.latched


def test_an_unreadable_latch_closes_the_gate(tmp_path: Path) -> None:
    folder = tmp_path / "file"
    folder.write_text("not a folder")
    clock = VirtualClock(start=1.7e9)
    watch = StopWatch(DriveClaim(folder, "127.0.0.1", 9090, clock=clock), lambda: None)
    assert watch.latched_at() == 1.7e9, "latched now, on the claim's clock"


def test_the_watch_thread_reads_the_latch_once_a_poll_on_the_claims_clock(tmp_path: Path) -> None:
    clock, fired = VirtualClock(start=1.7e9), []
    session = DriveSession(FakeLink(), claim=DriveClaim(tmp_path, "127.0.0.1", 9090, member="b", clock=clock))
    watch = StopWatch(DriveClaim(tmp_path, "127.0.0.1", 9090, member="a", clock=clock), lambda: fired.append(1))
    watch.start()
    try:
        assert clock.wait_for_waiters(1), "the watch never waited on the claim's clock"
        session.stop()  # page B latches a Stop between two polls of page A's watch
        clock.advance(POLL_S / 2)
        assert fired == [], "not read before the next poll"
        clock.advance(POLL_S / 2)
        assert fired == [1]
        clock.advance(60 * POLL_S)
        assert fired == [1], "one latch, answered once"
    finally:
        watch.close()


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "bridge"), [("ros2", "official"), ("ros2", "rs"), ("ros1", "official")])
def test_page_b_stop_stops_page_a_goal_and_refuses_the_next(
    tmp_path: Path, sim_factory, link_factory, ros: str, bridge: str
) -> None:
    sim = sim_factory(ros=ros, start_pose=START, bridge=bridge)
    link_a, link_b = link_factory(sim), link_factory(sim)  # two kernels: two links, two sockets
    watch = StopWatch(DriveClaim(tmp_path, "127.0.0.1", sim.port, member="a"), link_a.stop_goals).start()
    link_a.goal_gate = watch.latched_at
    try:
        handle = link_a.navigate_to(*FAR)  # A's Go to
        assert wait_until(lambda: sim.velocity[0] > 0.2, 10.0)
        claim_b = DriveClaim(tmp_path, "localhost", sim.port, member="b")  # B spells the chair otherwise
        with DriveSession(link_b, claim=claim_b) as session_b:
            session_b.stop()  # B's Stop: B runs no goal; A's goal must end all the same
            assert wait_until(lambda: sim.velocity == (0.0, 0.0), 2.0)
            x = sim.pose[0]
            assert wait_until(lambda: False, 1.0) is False and math.isclose(sim.pose[0], x, abs_tol=0.02)
            assert wait_until(lambda: handle.progress().status is GoalStatus.CANCELLED, 3.0), handle.progress()
            assert watch.fired == 1
            with pytest.raises(GoalsStopped):  # A's Go to again, under the latch
                link_a.navigate_to(*FAR)
            assert sim.goal_status == "cancelled" and math.isclose(sim.pose[0], x, abs_tol=0.02)
            session_b.release_stop()  # released where it was pressed
        again = link_a.navigate_to(*FAR)
        assert wait_until(lambda: again.progress().status is GoalStatus.MOVING, 10.0)
    finally:
        watch.close()
