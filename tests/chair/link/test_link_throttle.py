"""The automatic throttle's rate watch (pure): none at chair rates a screen keeps up with, one frame above."""

from __future__ import annotations

from pmk_nb.chair.link.streams.throttle import FRAME_MS, SCREEN_HZ, AutoThrottle


def feed(auto: AutoThrottle, hz: float, seconds: float, start: float = 0.0) -> list[int]:
    asks = []
    for i in range(int(hz * seconds)):
        got = auto.note(start + i / hz)
        if got is not None:
            asks.append(got)
    return asks


def test_rates_a_screen_keeps_up_with_are_never_throttled() -> None:
    for hz in (10.0, 40.0, 50.0, SCREEN_HZ):
        auto = AutoThrottle()
        assert feed(auto, hz, 5.0) == [] and auto.current_ms == 0
        assert auto.rate_hz is not None and abs(auto.rate_hz - hz) < 1.5


def test_a_faster_stream_is_throttled_once_to_one_frame() -> None:
    auto = AutoThrottle()
    assert feed(auto, 200.0, 5.0) == [FRAME_MS] and auto.current_ms == FRAME_MS == 17
    # through the throttle the rate looks lower: no release, no flapping
    assert feed(auto, 35.0, 5.0, start=10.0) == [] and auto.current_ms == FRAME_MS


def test_a_burst_shorter_than_a_window_does_not_throttle() -> None:
    auto = AutoThrottle()
    asks = [auto.note(t / 1000.0) for t in range(0, 300, 2)]  # 150 messages in 0.3 s, then calm
    asks += [auto.note(0.3 + i / 20.0) for i in range(1, 60)]
    assert [a for a in asks if a is not None] == [] and auto.current_ms == 0
