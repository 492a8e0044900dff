"""Time is an input (issue 39): the product modules that decide by time read it and wait on it only
through a :class:`pmk_nb.clock.Clock` they are given, never the wall clock directly.

An AST scan of :data:`CLOCKED` (the modules converted so far, listed by name: the list only grows).
A module offends when it names ``time.time``/``monotonic``/``sleep``/``perf_counter`` (called or passed
as a value), imports one of them from ``time``, sleeps with ``asyncio.sleep``, or reads an event loop's
``time()``. ``pmk_nb/clock.py`` itself is the one place that reads the real clocks.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
WALL_CLOCK = {"time", "monotonic", "sleep", "perf_counter", "monotonic_ns", "perf_counter_ns", "time_ns"}

#: module -> what in it decides by time (one line each)
CLOCKED: dict[str, str] = {
    "pmk_nb/chair/link/goals/goal.py": "a goal's sent / last news / cancel times, GoalHandle.wait",
    "pmk_nb/chair/link/goals/goal_watch.py": "acceptance, silence and cancel deadlines, its tick, the zero burst",
    "pmk_nb/chair/link/goals/goal_stop.py": "the Stop's zero burst and its repeats",
    "pmk_nb/chair/link/goals/goal_attach.py": "when the chair's goal status was last heard (a re-attach)",
    "pmk_nb/chair/link/goals/goal_topic.py": "the goal-topic poller and its no-progress deadline",
    "pmk_nb/chair/link/transport/side_channel.py": "the side channel's zero burst",
    "pmk_nb/chair/link/goals/navigate.py": "the goal's clock",
    "pmk_nb/chair/link/goals/heartbeat.py": "the goal heartbeat's beats",
    "pmk_nb/chair/link/query/connectivity.py": "the connection test's deadline and elapsed time",
    "pmk_nb/chair/link/transport/backoff.py": "the reconnect backoff (its delays run in the transport's factory)",
    "pmk_nb/robot/goalwatch.py": "the watchdog's silence and Stop debounce",
    "pmk_nb/robot/simnode.py": "the simulator node's physics",
    "pmk_nb/robot/wheels.py": "the stack set-up's reported durations",
    "pmk_nb/sim/engine.py": "the simulator's physics and loop rates",
    "pmk_nb/sim/navigation.py": "the navigator's feedback rate, a goal's navigation time",
    "pmk_nb/sim/navigation_ros1.py": "how long finished move_base goals stay listed",
    "pmk_nb/sim/navgoal.py": "when a goal started",
    "pmk_nb/sim/action_status.py": "how long finished Nav2 goals stay listed",
    "pmk_nb/classroom/cap.py": "a seat's start",
    "pmk_nb/drive/claim.py": "the drive claim's beats, staleness and Stop latch",
    "pmk_nb/drive/stopwatch.py": "the Stop latch's polls",
    "pmk_nb/drive/session.py": "the drive publisher's ticks and the deadman",
    "pmk_nb/ui/live/render_loop.py": "the live view's frame pacing",
    "pmk_nb/ui/live/gestures.py": "wheel bursts",
    "pmk_nb/ui/home/preview.py": "the preview's wait for its link",
}


def offences(source: str) -> list[str]:
    """Where ``source`` reads or waits on the real clock itself (line: what)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            if node.value.id == "time" and node.attr in WALL_CLOCK:
                found.append(f"{node.lineno}: time.{node.attr}")
            elif node.value.id == "asyncio" and node.attr == "sleep":
                found.append(f"{node.lineno}: asyncio.sleep")
        if isinstance(node, ast.ImportFrom) and node.module == "time":
            found += [f"{node.lineno}: from time import {a.name}" for a in node.names if a.name in WALL_CLOCK]
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "time":
            owner = node.func.value
            loop = isinstance(owner, ast.Name) and owner.id == "loop"
            running = isinstance(owner, ast.Call) and "get_running_loop" in ast.dump(owner.func)
            if loop or running:
                found.append(f"{node.lineno}: an event loop's time()")
    return found


@pytest.mark.parametrize("module", sorted(CLOCKED))
def test_a_clocked_module_reads_time_only_through_its_clock(module: str) -> None:
    path = ROOT / module
    assert path.is_file(), f"{module} is listed in CLOCKED but does not exist (moved? update the list)"
    found = offences(path.read_text(encoding="utf-8"))
    assert not found, f"{module} ({CLOCKED[module]}) reads the real clock itself; take a pmk_nb.clock.Clock: {found}"


def test_the_scan_finds_each_way_of_reading_the_real_clock() -> None:
    source = (
        "import asyncio, time\n"
        "from time import monotonic\n"
        "def f(clock=time.monotonic):\n"
        "    time.sleep(1)\n"
        "    t = time.time()\n"
        "    loop = asyncio.get_running_loop()\n"
        "    loop.time()\n"
        "    asyncio.get_running_loop().time()\n"
        "    await_me = asyncio.sleep(1)\n"
        "    time.strftime('%H')\n"
        "    clock.now()\n"
    )
    assert sorted(offences(source)) == [
        "2: from time import monotonic",
        "3: time.monotonic",
        "4: time.sleep",
        "5: time.time",
        "7: an event loop's time()",
        "8: an event loop's time()",
        "9: asyncio.sleep",
    ]
