"""One driver per chair and a Stop that holds on every page (issue 30, finding 3), and two low
findings of the drive path: an over-long integer in a joystick message, a new page id after Stop.

Two "kernels" are two :class:`DriveClaim` objects (two sessions) on the same folder, with a fake
clock; the sessions' publisher threads are not started: their ticks are called by hand.
"""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.clock import VirtualClock
from pmk_nb.drive import DriveClaim, DriveGate, DriveSession, Hold, SpeedLimits, StopReason, parse_stick_message
from pmk_nb.drive.stick import StickEvent, StickMessageError


class Clock(VirtualClock):
    """The virtual clock, with ``t`` to read and move it (``clock.t += 0.05`` advances 50 ms)."""

    def __init__(self, t: float = 1_000_000.0) -> None:
        super().__init__(t)

    @property
    def t(self) -> float:
        return self.now()

    @t.setter
    def t(self, value: float) -> None:
        self.advance(value - self.now())


def claims(tmp_path: Path, clock: Clock, n: int = 2) -> list[DriveClaim]:
    return [DriveClaim(tmp_path / "drive", "127.0.0.1", 9090, member=f"k{i}", clock=clock) for i in range(n)]


def test_the_first_page_to_drive_holds_the_chair_the_others_see_it_until_it_goes_quiet(tmp_path: Path) -> None:
    clock = Clock()
    a, b = claims(tmp_path, clock)
    assert a.view().hold is Hold.FREE and b.view().hold is Hold.FREE
    assert a.acquire().hold is Hold.MINE
    seen = b.acquire()  # B cannot simply claim it
    assert seen.hold is Hold.OTHER_DRIVER and seen.owner_since == clock.t and not seen.may_drive
    clock.t += 2.5
    assert a.view().hold is Hold.MINE  # A's heartbeat (written at most once a second)
    clock.t += 2.5
    assert b.view().hold is Hold.OTHER_DRIVER  # 2.5 s since A's heartbeat: still alive
    clock.t += 1.0  # A's kernel died 3.5 s ago: it blocks nobody any more
    assert b.view().hold is Hold.FREE and b.acquire().hold is Hold.MINE
    assert a.view().hold is Hold.OTHER_DRIVER  # A comes back: B drives now
    folder = tmp_path / "drive"
    assert stat.S_IMODE(os.stat(folder).st_mode) == 0o700 and stat.S_IMODE(os.stat(a.path).st_mode) == 0o600
    assert a.path.name == "loopback_9090.json"  # the resolved address (issue 38): every spelling of it
    assert DriveClaim(folder, "127.0.0.1", 9091, clock=clock).view().hold is Hold.FREE  # another chair


def test_take_over_is_explicit_and_leaving_frees_the_chair(tmp_path: Path) -> None:
    clock = Clock()
    a, b = claims(tmp_path, clock)
    a.acquire()
    clock.t += 60.0
    a.view()
    assert b.take_over().hold is Hold.MINE
    assert a.view().hold is Hold.OTHER_DRIVER and a.view().owner_since == clock.t
    b.leave()
    assert a.view().hold is Hold.FREE
    assert json.loads(a.path.read_text())["owner"] is None


def test_a_stop_on_any_page_holds_until_that_page_releases_it(tmp_path: Path) -> None:
    clock = Clock()
    a, b, c = claims(tmp_path, clock, 3)
    a.acquire()
    b.view()
    assert b.stop().hold is Hold.OTHER_DRIVER  # B stopped while A drives: B sees A as the driver
    seen = a.view()
    assert seen.hold is Hold.STOPPED_ELSEWHERE and seen.stop_at == clock.t and seen.setter_live
    assert a.release_stop().hold is Hold.STOPPED_ELSEWHERE  # A cannot release B's Stop
    assert a.release_stop(force=True).hold is Hold.STOPPED_ELSEWHERE  # not even explicitly, B is open
    assert a.take_over().hold is Hold.STOPPED_ELSEWHERE  # and taking over does not pass it
    assert c.acquire().hold is Hold.STOPPED_ELSEWHERE
    clock.t += 3600.0  # time does not clear a Stop
    assert a.view().hold is Hold.STOPPED_ELSEWHERE and not a.view().setter_live
    assert b.release_stop().hold is Hold.OTHER_DRIVER  # released on B; A (who took over) drives again
    assert a.view().hold is Hold.MINE and c.view().hold is Hold.OTHER_DRIVER


def test_a_stop_whose_page_is_gone_is_released_only_explicitly(tmp_path: Path) -> None:
    clock = Clock()
    a, b = claims(tmp_path, clock)
    a.acquire()
    b.stop()
    b.leave()  # B's panel closes: its Stop stays
    clock.t += 10.0
    assert a.view().hold is Hold.STOPPED_ELSEWHERE and not a.view().setter_live
    assert a.acquire().hold is Hold.STOPPED_ELSEWHERE
    assert a.release_stop(force=True).hold is Hold.MINE


def test_a_damaged_file_is_an_empty_state_and_is_rewritten(tmp_path: Path) -> None:
    clock = Clock()
    a, b = claims(tmp_path, clock)
    a.path.parent.mkdir(parents=True)
    a.path.write_text("{broken")
    assert a.acquire().hold is Hold.MINE and b.view().hold is Hold.OTHER_DRIVER
    a.path.write_text(json.dumps({"owner": 5, "pages": {"x": "y"}, "stop_by": "k1", "stop_at": True}))
    assert a.view().hold is Hold.STOPPED_ELSEWHERE  # a latch survives a damaged file


# -- two sessions on one folder (two kernels), fake link, ticks by hand ----------------------------
class FakeLink:
    def __init__(self, clock: Any) -> None:
        self.sent: list[tuple[float, float]] = []
        self.clock = clock

    @property
    def is_connected(self) -> bool:
        return True

    def latest_odom(self) -> Any:
        return type("Odom", (), {"received": self.clock()})()

    def publish_cmd_vel(self, v: float, w: float, topic: str | None = None) -> bool:
        self.sent.append((v, w))
        return True


def msg(page: str, seq: int, press: int, t: float, held: bool = True) -> str:
    body = {"page": page, "seq": seq, "press": press, "t": t * 1000.0, "x": 0.0, "y": 1.0, "held": held}
    return json.dumps({**body, "hidden": False})


def tick(session: DriveSession) -> tuple[float, float] | None:
    """One publisher tick, as the thread does it."""
    blocked = session._blocked()
    with session._lock:
        if blocked is not None and session.gate.driving:
            session.gate.stop(blocked)
        return session.gate.tick(session._clock.now(), True)


def test_stop_on_page_b_stops_page_a_at_its_next_tick_and_a_drives_only_after_b_releases(tmp_path: Path) -> None:
    mono, wall = Clock(50.0), Clock()
    a_claim, b_claim = claims(tmp_path, wall)
    a = DriveSession(FakeLink(mono), SpeedLimits(), clock=mono, claim=a_claim)
    b = DriveSession(FakeLink(mono), SpeedLimits(), clock=mono, claim=b_claim)
    a.feed(msg("pa", 1, 1, mono.t))
    assert tick(a) == pytest.approx((0.5, 0.0)) and tick(b) is None
    b.feed(msg("pb", 1, 1, mono.t))  # B's stick while A drives: refused
    assert not b.driving and b.gate.last_stop is StopReason.OTHER_DRIVER
    assert b.claim_view is not None and b.claim_view.hold is Hold.OTHER_DRIVER
    b.stop()  # B's Stop: B's zero, and A stops at its next tick
    assert tick(b) == (0.0, 0.0)
    mono.t += 0.05
    a.feed(msg("pa", 2, 1, mono.t))  # A's finger is still down
    assert tick(a) == (0.0, 0.0) and a.gate.last_stop is StopReason.STOPPED_ELSEWHERE
    mono.t += 0.05
    a.feed(msg("pa", 3, 2, mono.t))  # A presses anew: still stopped from B
    assert tick(a) is None and not a.driving
    a.feed(msg("pa-reloaded", 1, 5, mono.t))  # nor with a new page id
    assert tick(a) is None and not a.driving
    b.release_stop()
    mono.t += 0.05
    a.feed(msg("pa-reloaded", 2, 6, mono.t))  # released on B: A's next press drives
    assert tick(a) == pytest.approx((0.5, 0.0))


def test_take_over_stops_the_previous_driver_at_its_next_tick(tmp_path: Path) -> None:
    mono, wall = Clock(50.0), Clock()
    a_claim, b_claim = claims(tmp_path, wall)
    a = DriveSession(FakeLink(mono), clock=mono, claim=a_claim)
    b = DriveSession(FakeLink(mono), clock=mono, claim=b_claim)
    a.feed(msg("pa", 1, 1, mono.t))
    assert tick(a) is not None
    assert b.take_over() is not None and b.claim_view is not None and b.claim_view.hold is Hold.MINE
    mono.t += 0.05
    a.feed(msg("pa", 2, 1, mono.t))
    assert tick(a) == (0.0, 0.0) and a.gate.last_stop is StopReason.OTHER_DRIVER
    a.feed(msg("pa", 3, 2, mono.t))
    assert tick(a) is None
    b.feed(msg("pb", 1, 1, mono.t))
    assert tick(b) == pytest.approx((0.5, 0.0))
    a.close()
    b.close()


# -- the two low findings ---------------------------------------------------------------------------
@pytest.mark.parametrize("field", ["t", "x", "y", "seq", "press"])
def test_an_over_long_integer_is_refused_not_an_overflow(field: str) -> None:
    body = {"page": "p", "seq": 1, "press": 1, "t": 1.0, "x": 0, "y": 0, "held": True, "hidden": False}
    text = json.dumps({**body, field: 10**400})
    assert len(text) <= 512
    with pytest.raises(StickMessageError) as err:
        parse_stick_message(text)
    assert err.value.field == field
    session = DriveSession(FakeLink(Clock()))
    assert session.feed(text) is None and session.invalid == 1  # the kernel callback does not raise


def test_a_new_page_id_does_not_clear_the_latch_after_stop() -> None:
    gate = DriveGate(SpeedLimits())
    gate.on_event(StickEvent("p1", 1, 1, 0.0, 0.0, 1.0, True), 0.01)
    assert gate.tick(0.02, True) is not None
    gate.stop()
    assert gate.tick(0.03, True) == (0.0, 0.0)
    # the same finger, now under another page id (a script, or late messages of a reload)
    gate.on_event(StickEvent("p2", 1, 1, 0.04, 0.0, 1.0, True), 0.05)
    assert gate.tick(0.06, True) is None and not gate.driving
    gate.on_event(StickEvent("p2", 2, 2, 0.07, 0.0, 1.0, True), 0.08)  # a new press of the new page
    assert gate.tick(0.09, True) == pytest.approx((0.5, 0.0))


def test_an_unusable_shared_folder_drives_nothing(tmp_path: Path) -> None:
    blocker = tmp_path / "not-a-folder"
    blocker.write_text("a file where the folder should be")
    mono = Clock(50.0)
    session = DriveSession(FakeLink(mono), clock=mono, claim=DriveClaim(blocker, "127.0.0.1", 9090))
    session.feed(msg("p", 1, 1, mono.t))
    assert not session.driving and session.gate.last_stop is StopReason.NO_CLAIM
    assert tick(session) is None and not session.push(0.3, 0.0)


def test_a_press_is_published_at_once_not_at_the_next_tick() -> None:
    """The first command of a press leaves when the page's message is in, not at the publisher's next
    tick (here a minute away, standing for the up to 50 ms a press waited at 20 Hz)."""
    clock = Clock()
    link = TickCounting(clock)
    session = DriveSession(link, clock=clock)
    session.period = 60.0
    session.start()
    try:
        assert clock.wait_for_waiters(1), "the publisher thread waits for its next tick"
        assert link.ticks == 1 and link.sent == [], "the first tick ran, with nothing to send"
        session.feed(msg("p", 1, 1, 5.0))
        clock.advance(0.0)  # no time passes: only the kicked tick runs
        assert link.ticks == 2 and len(link.sent) == 1 and link.sent[0][0] > 0.0, "published at once"
        clock.advance(59.9)
        assert link.ticks == 2 and len(link.sent) == 1, "nothing until the next tick"
        clock.advance(0.1)
        assert link.sent[1:] == [(0.0, 0.0)] and session.gate.last_stop is StopReason.KEEPALIVE
    finally:
        session.close()


class TickCounting(FakeLink):
    """Counts the publisher's ticks (it reads the odometry once per tick)."""

    ticks = 0

    def latest_odom(self) -> Any:
        self.ticks += 1
        return super().latest_odom()


RATE = 16.0  # Hz: a period of 1/16 s, exact in binary, so tick times never round past a deadline
GO = (0.3, 0.0)


def started(link: FakeLink, clock: Clock) -> DriveSession:
    session = DriveSession(link, clock=clock, rate=RATE).start()
    assert clock.wait_for_waiters(1), "the publisher thread waits for its next tick"
    return session


def test_an_idle_session_ticks_slowly_and_any_input_wakes_it() -> None:
    """Nothing to send: the publisher ticks every IDLE_PERIOD_S (0.25 s), not at its driving rate (ten
    classroom pages read their claim files 200 times a second for nothing); a push, a release and
    the Stop button each reach the chair at once, not at the next idle tick."""
    clock = Clock()
    link = TickCounting(clock)
    session = started(link, clock)
    try:
        clock.advance(1.0)
        assert link.ticks == 5 and link.sent == [], "the first tick and one every 0.25 s while idle"
        assert session.push(*GO)
        clock.advance(0.0)
        assert link.sent == [GO] and link.ticks == 6, "a push is published at once"
        clock.advance(0.125)
        assert link.sent == [GO] * 3 and link.ticks == 8, "driving ticks at the full rate"
        session.release()
        clock.advance(0.0)
        assert link.sent == [GO] * 3 + [(0.0, 0.0)], "the release's zero goes at once"
        clock.advance(10.0)
        assert link.ticks == 9 + 40 and len(link.sent) == 4, "idle again: silence, four ticks a second"
        session.stop()
        clock.advance(0.0)
        assert link.sent[4:] == [(0.0, 0.0)], "the Stop button's zero goes at once, though idle"
    finally:
        session.close()


def test_after_300_ms_of_silence_one_zero_and_nothing_after() -> None:
    """The keepalive: a push 0.3 s old stops the chair at the next tick with one zero; commands older
    than 0.2 s are not sent meanwhile; nothing follows the zero."""
    clock = Clock()
    link = FakeLink(clock)
    session = started(link, clock)
    try:
        session.push(*GO)
        clock.advance(0.25)  # ticks at 0, 1/16, 2/16, 3/16 send; 4/16 (0.25 s old) is skipped
        assert link.sent == [GO] * 4 and session.gate.stats.skipped_ticks == 1
        clock.advance(0.0625)  # 5/16 s: more than 0.3 s without news
        assert link.sent == [GO] * 4 + [(0.0, 0.0)] and session.gate.last_stop is StopReason.KEEPALIVE
        clock.advance(5.0)
        assert len(link.sent) == 5, "one zero, then silence"
        assert not session.push(*GO), "the stopped press drives no more"
    finally:
        session.close()


def test_odometry_older_than_350_ms_stops_the_chair_though_the_pushes_go_on() -> None:
    """A stale link (odometry frozen) stops the chair at the first tick past ``odom_fresh``."""

    class FrozenOdometry(FakeLink):
        def __init__(self, clock: Clock) -> None:
            super().__init__(clock)
            self.at = clock.now()

        def latest_odom(self) -> Any:
            return type("Odom", (), {"received": self.at})()

    clock = Clock()
    link = FrozenOdometry(clock)
    session = started(link, clock)
    try:
        for step in (0.125, 0.125, 0.0625):  # a push every 1/8 s: the page's keepalive holds
            assert session.push(*GO)
            clock.advance(step)
        assert link.sent == [GO] * 6, "0 to 5/16 s: odometry at most 0.3125 s old"
        clock.advance(0.0625)  # 6/16 s = 0.375 s > 0.35 s
        assert link.sent == [GO] * 6 + [(0.0, 0.0)] and session.gate.last_stop is StopReason.LINK
        assert not session.push(*GO)
        clock.advance(5.0)
        assert len(link.sent) == 7, "one zero, then silence"
    finally:
        session.close()
