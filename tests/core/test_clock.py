"""The virtual clock (issue 39): time moves only on advance, waiters wake in deadline order and run
before advance returns, an event wakes a wait at once; the real clock waits on the event."""

from __future__ import annotations

import asyncio
import concurrent.futures
import threading

import pytest

from pmk_nb.clock import MONOTONIC, WALL, AsyncPacer, Clock, MonotonicClock, VirtualClock


def _ticker(clock: Clock, period: float, stop: threading.Event, seen: list[float], name: str = "") -> threading.Thread:
    def run() -> None:
        while not clock.wait(stop, period):
            seen.append(clock.now())

    thread = threading.Thread(target=run, name=name or "ticker", daemon=True)
    thread.start()
    return thread


def test_time_moves_only_on_advance() -> None:
    clock = VirtualClock(start=50.0)
    assert clock.now() == clock() == 50.0
    clock.advance(0.25)
    assert clock.now() == 50.25
    with pytest.raises(ValueError):
        clock.advance(-1.0)


def test_a_periodic_thread_ticks_exactly_once_per_period_of_advanced_time() -> None:
    clock, stop, seen = VirtualClock(start=0.0), threading.Event(), []
    thread = _ticker(clock, 0.0625, stop, seen)  # a period exact in binary: no rounding at the edges
    assert clock.wait_for_waiters(1)
    clock.advance(1.0)
    assert seen == [0.0625 * i for i in range(1, 17)], "each tick ran at its own virtual time"
    clock.advance(0.0625 - 2**-20)
    assert len(seen) == 16, "no tick before its deadline"
    clock.advance(2**-20)
    assert len(seen) == 17
    stop.set()
    thread.join(10.0)
    assert not thread.is_alive()


def test_waiters_wake_in_deadline_order_each_seeing_its_own_time() -> None:
    clock, order = VirtualClock(start=0.0), []
    lock = threading.Lock()

    def sleeper(seconds: float) -> None:
        clock.sleep(seconds)
        with lock:
            order.append((seconds, clock.now()))

    threads = [threading.Thread(target=sleeper, args=(s,), daemon=True) for s in (0.3, 0.1, 0.2)]
    for t in threads:
        t.start()
    assert clock.wait_for_waiters(3)
    clock.advance(0.15)
    assert order == [(0.1, 0.1)], "advance returns after the woken thread ran; the others still wait"
    clock.advance(10.0)
    assert order == [(0.1, 0.1), (0.2, 0.2), (0.3, 0.3)]
    assert clock.waiting == 0


def test_a_set_event_ends_a_wait_without_time_moving() -> None:
    clock, event, result = VirtualClock(start=0.0), threading.Event(), []
    thread = threading.Thread(target=lambda: result.append(clock.wait(event, 60.0)), daemon=True)
    thread.start()
    assert clock.wait_for_waiters(1)
    event.set()
    thread.join(10.0)
    assert result == [True] and clock.now() == 0.0


def test_advance_zero_lets_a_kicked_thread_run_its_turn() -> None:
    """An event set before advance(0): the thread it wakes has run and waits again when advance returns."""
    clock, kick, runs = VirtualClock(start=0.0), threading.Event(), []

    def run() -> None:
        while True:
            if clock.wait(kick, 60.0):
                kick.clear()
            runs.append(clock.now())
            if len(runs) >= 3:
                return

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    assert clock.wait_for_waiters(1)
    kick.set()
    clock.advance(0.0)
    assert runs == [0.0]
    clock.advance(60.0)
    assert runs == [0.0, 60.0]


def test_a_wait_already_past_its_deadline_returns_the_event_state() -> None:
    clock, event = VirtualClock(), threading.Event()
    assert clock.wait(event, 0.0) is False
    event.set()
    assert clock.wait(event, 0.0) is True


def test_the_real_clock_waits_on_the_event() -> None:
    event = threading.Event()
    event.set()
    assert isinstance(MONOTONIC, MonotonicClock)
    assert MONOTONIC.wait(event, 60.0) is True  # at once: the event is set
    assert MONOTONIC.now() <= MONOTONIC.now()


def test_the_wall_clock_reads_epoch_seconds_and_waits_on_the_event() -> None:
    event = threading.Event()
    event.set()
    assert WALL.now() > 1.6e9 and MONOTONIC.now() < WALL.now()  # epoch seconds, not the monotonic count
    assert WALL.wait(event, 60.0) is True


def _loop_thread() -> tuple[asyncio.AbstractEventLoop, threading.Thread]:
    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, name="test-loop", daemon=True)
    thread.start()
    return loop, thread


def test_an_asyncio_task_paced_by_a_virtual_clock_runs_each_due_step_before_advance_returns() -> None:
    clock, steps = VirtualClock(start=0.0), []
    before = set(threading.enumerate())
    loop, thread = _loop_thread()

    async def ticker() -> None:
        pacer = AsyncPacer(clock)
        while True:
            await pacer.sleep(0.25)
            steps.append(clock.now())

    task = asyncio.run_coroutine_threadsafe(ticker(), loop)
    try:
        assert clock.wait_for_waiters(1)
        clock.advance(0.2)
        assert steps == []
        clock.advance(0.8)
        assert steps == [0.25, 0.5, 0.75, 1.0], "every step due in the span ran, each at its own time"
        clock.advance(0.25)
        assert steps == [0.25, 0.5, 0.75, 1.0, 1.25]
        pacers = [t for t in set(threading.enumerate()) - before if t.name == "pmk-pacer"]
        assert len(pacers) == 1
    finally:
        task.cancel()
        concurrent.futures.wait([task], timeout=10.0)
        loop.call_soon_threadsafe(loop.stop)
        thread.join(10.0)
    pacers[0].join(10.0)
    assert not pacers[0].is_alive(), "a cancelled task ends its pacer's thread"
    assert clock.waiting == 0
    loop.close()


def test_a_pacer_on_the_real_clock_is_asyncio_sleep() -> None:
    pacer, started = AsyncPacer(MONOTONIC), []

    async def once() -> None:
        await pacer.sleep(0.0)
        started.append(True)

    asyncio.run(once())
    assert started == [True]
    assert pacer._thread is None, "the real clock needs no thread"
