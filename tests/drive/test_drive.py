"""The drive core: stick -> twist within limits, message validation, clock offset, the deadman gate."""

from __future__ import annotations

import json
import math
from typing import Any

import pytest

from pmk_nb.drive import (
    ClockOffset,
    DriveGate,
    GateTiming,
    SpeedLimits,
    StickMessageError,
    StopReason,
    parse_stick_message,
    stick_to_twist,
)
from pmk_nb.drive.stick import StickEvent

LIM = SpeedLimits()  # 0.5 m/s, 0.8 rad/s


def msg(**kw: Any) -> str:
    base = {"page": "p1", "seq": 1, "press": 1, "t": 1000.0, "x": 0.0, "y": 1.0, "held": True, "hidden": False}
    return json.dumps({**base, **kw})


# -- limits ------------------------------------------------------------------------------------------
def test_full_stick_gives_the_profile_limits_and_slow_mode_scales_them() -> None:
    assert stick_to_twist(0.0, 1.0, LIM) == pytest.approx((0.5, 0.0))
    assert stick_to_twist(1.0, 0.0, LIM) == pytest.approx((0.0, -0.8))  # right turns clockwise
    assert stick_to_twist(-1.0, 0.0, LIM) == pytest.approx((0.0, 0.8))
    assert stick_to_twist(0.0, -1.0, LIM, slow=True) == pytest.approx((-0.2, 0.0))
    custom = SpeedLimits(max_linear=1.2, max_angular=0.5, slow_factor=0.5)
    assert stick_to_twist(0.0, 1.0, custom, slow=True) == pytest.approx((0.6, 0.0))


def test_dead_zone_sends_zero_and_speed_grows_from_its_edge() -> None:
    assert stick_to_twist(0.05, 0.05, LIM) == (0.0, 0.0)
    v, _ = stick_to_twist(0.0, LIM.dead_zone + 0.01, LIM)
    assert 0.0 < v < 0.01
    v_half, _ = stick_to_twist(0.0, 0.56, LIM)
    assert v_half == pytest.approx(0.25, abs=1e-6)
    assert stick_to_twist(math.nan, 0.5, LIM) == (0.0, 0.0)


def test_limits_refuse_nonsense_and_clamp_scripts() -> None:
    for bad in ({"max_linear": 0}, {"max_angular": -1}, {"slow_factor": 1.5}, {"dead_zone": 1.0}):
        with pytest.raises(ValueError):
            SpeedLimits(**bad)
    assert LIM.clamp(3.0, -9.0) == (0.5, -0.8)
    assert LIM.clamp(math.inf, 0.1) == (0.0, 0.1)


# -- messages ----------------------------------------------------------------------------------------
def test_a_page_message_is_parsed_and_pulled_onto_the_unit_disc() -> None:
    event = parse_stick_message(msg(x=1.0, y=1.0, t=2500))
    assert event.t == 2.5 and event.held and not event.hidden
    assert math.hypot(event.x, event.y) == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("text", "field"),
    [
        (msg(x=2.0), "x"),
        (msg(y=float("nan")), "y"),
        (msg(held="yes"), "held"),
        (msg(seq=-1), "seq"),
        (msg(seq=True), "seq"),
        (msg(t=-5), "t"),
        (msg(page=""), "page"),
        (msg(extra=1), "extra"),
        (json.dumps({"seq": 1}), "held"),
        ("[1, 2]", None),
        ("not json", None),
        ("x" * 600, None),
        (None, None),
    ],
)
def test_anything_else_from_the_page_is_refused(text: Any, field: str | None) -> None:
    with pytest.raises(StickMessageError) as err:
        parse_stick_message(text)
    assert err.value.field == field


# -- clock offset ------------------------------------------------------------------------------------
def test_offset_is_the_smallest_delay_seen_and_drifts_up_only_slowly() -> None:
    clock = ClockOffset()
    clock.observe(100.050, 2.000)  # 50 ms delivery
    clock.observe(100.110, 2.100)  # 10 ms delivery: the better estimate
    clock.observe(100.400, 2.200)  # 200 ms (a slow one) does not raise it
    assert clock.kernel_time(2.200) == pytest.approx(100.210)
    # a page clock that runs slower by 50 ppm is followed within the drift allowance
    clock.observe(1100.0 + 0.01 + 0.05, 1002.0)
    assert clock.kernel_time(1002.0) == pytest.approx(1100.01 + 0.05, abs=1e-3)


# -- the gate ----------------------------------------------------------------------------------------
class Page:
    """A page whose clock is 1000 s behind the kernel's, delivering in ``delay`` s."""

    def __init__(self, gate: DriveGate, name: str = "p1") -> None:
        self.gate, self.name, self.seq, self.press = gate, name, 0, 0

    def send(
        self,
        now: float,
        *,
        held: bool = True,
        x: float = 0.0,
        y: float = 1.0,
        delay: float = 0.01,
        hidden: bool = False,
        new_press: bool = False,
    ) -> None:
        self.seq += 1
        self.press += int(new_press)
        event = StickEvent(self.name, self.seq, self.press, now - delay - 1000.0, x, y, held, hidden)
        self.gate.on_event(event, now)


def test_commands_only_while_held_then_one_zero_then_silence() -> None:
    gate = DriveGate(LIM)
    page = Page(gate)
    assert gate.tick(0.0, True) is None
    page.send(1.0, new_press=True)
    assert gate.tick(1.02, True) == pytest.approx((0.5, 0.0))
    page.send(1.1)
    assert gate.tick(1.12, True) == pytest.approx((0.5, 0.0))
    page.send(1.15, held=False)
    assert gate.tick(1.16, True) == (0.0, 0.0)
    assert [gate.tick(1.2 + i * 0.05, True) for i in range(5)] == [None] * 5
    assert gate.last_stop is StopReason.RELEASED and gate.stats.zeros == 1


def test_a_late_command_is_dropped_never_sent() -> None:
    gate = DriveGate(LIM)
    page = Page(gate)
    page.send(1.0, new_press=True)  # calibrates the clock: 10 ms delivery
    page.send(2.0, delay=0.25)  # arrives 250 ms after it was sent
    assert gate.stats.dropped_late == 1
    # the fresh one from 1.0 s is now 1 s old: the gate stops rather than send it
    assert gate.tick(2.0, True) == (0.0, 0.0)
    assert gate.last_stop is StopReason.KEEPALIVE
    # between 200 and 300 ms of age: nothing is sent (not even the last command)
    page.send(3.0, new_press=True)
    assert gate.tick(3.25, True) is None and gate.stats.skipped_ticks == 1
    assert gate.driving


def test_missing_keepalives_stop_with_one_zero_and_the_press_is_over() -> None:
    gate = DriveGate(LIM)
    page = Page(gate)
    page.send(1.0, new_press=True)
    assert gate.tick(1.05, True) is not None
    assert gate.tick(1.32, True) == (0.0, 0.0)  # 310 ms without news
    assert gate.last_stop is StopReason.KEEPALIVE
    # the kernel was busy: the queued keepalives of the same press arrive now, the last one fresh
    page.send(1.35)
    assert gate.tick(1.36, True) is None and not gate.driving
    page.send(1.4, new_press=True)  # the user presses again
    assert gate.tick(1.41, True) == pytest.approx((0.5, 0.0))


def test_stale_link_hidden_page_and_stop_button_each_stop_with_one_zero() -> None:
    for how, reason in (("link", StopReason.LINK), ("hidden", StopReason.HIDDEN), ("button", StopReason.STOP_BUTTON)):
        gate = DriveGate(LIM)
        page = Page(gate)
        page.send(1.0, new_press=True)
        assert gate.tick(1.02, True) is not None
        if how == "hidden":
            page.send(1.05, hidden=True)
        elif how == "button":
            gate.stop()
        assert gate.tick(1.06, how != "link") == (0.0, 0.0), how
        assert gate.tick(1.1, True) is None, how
        assert gate.last_stop is reason
        page.send(1.12)  # the same press, still held: never drives again
        assert gate.tick(1.13, True) is None, how


def test_duplicates_out_of_order_and_a_new_page_load() -> None:
    gate = DriveGate(LIM)
    page = Page(gate)
    page.send(1.0, new_press=True)
    stale = StickEvent("p1", 1, 1, 0.0, 0.0, -1.0, True)  # an old sequence number
    gate.on_event(stale, 1.01)
    assert gate.stats.ignored == 1 and gate.tick(1.02, True) == pytest.approx((0.5, 0.0))
    reload = Page(gate, "p2")  # a reloaded page starts its counters and clock again
    reload.send(1.05, held=True, y=-1.0, new_press=True)
    assert gate.tick(1.06, True) == pytest.approx((-0.5, 0.0))


def test_slow_mode_and_python_commands() -> None:
    gate = DriveGate(LIM, GateTiming())
    gate.slow = True
    gate.on_twist(2.0, 0.0, 5.0)
    assert gate.tick(5.05, True) == pytest.approx((0.2, 0.0))
    assert gate.tick(5.35, True) == (0.0, 0.0)  # no push for 350 ms
    assert not gate.on_twist(0.1, 0.1, 6.0)  # stopped: refused until released
    assert gate.tick(6.01, True) is None
    gate.release()
    assert gate.on_twist(0.1, 0.1, 6.1)  # a new press
    assert gate.tick(6.11, True) == pytest.approx((0.1, 0.1))
