"""Root conftest: registers the shared fixture modules so every test file can use them.

Tests mirror the package tree (``tests/<package>/``, ``tests/chair/link/``, ...); the tests of the whole
system sit in folders of their own, and three of them are ``heavy`` (``make check``, the fast tier, leaves
them out): ``tests/browser/`` (Chromium), ``tests/real/`` (real ROS stacks) and ``tests/kernels/`` (notebook
kernels, Voilà). A test marked ``browser`` elsewhere is heavy too. ``tests/project/test_tree.py`` holds this
layout. (pytest-xdist's ``--dist loadgroup`` would keep the heavy tests on one worker, but with pytest
9.2 it does not group: xdist 3.8 writes the group into ``item._nodeid``, which pytest 9.2 no longer
reads. ``make test`` therefore uses ``-n 2``.)

Browser modules run first, and ``make test`` uses ``--dist worksteal``: plain load scheduling gave
the first worker an initial chunk of 297 tests holding every browser test (about 1200 s of the
1348 s run) while the second finished the rest and waited; with the browser tests at the head of
one worker's queue, an idle worker steals the light tests from its tail instead. Browser tests
still run one at a time (a lock per run, taken before the test's timeout starts): their timing
goals (a stop within 0.5 s) are measured as they were, one browser and one Voilà at a time.

The ``realtime`` tier (issue 39): what must run in real time (real browsers, real bridges, the
simulated chair on its own clock, SSH servers, soaks). conftest marks it: every heavy test, and every
test that uses one of :data:`REALTIME_FIXTURES` (directly or through another fixture); a test may also
be marked ``@pytest.mark.realtime`` by hand. Its assertions keep margins a busy 2-core machine meets
and it waits on events, not on sleeps. Every other test is a unit test: time is an input there
(``pmk_nb.clock.VirtualClock``), and ``tests/project/test_no_wall_clock.py`` fails when one sleeps
or asserts on the wall clock.

``make check`` is the fast loop: it also leaves out tests marked ``slow`` (more than half a second on an
idle machine: a simulated chair driving somewhere, a subprocess, a real-file sweep). So that the tier
stays fast as tests are added, every run lists the unmarked tests that took more than a second.
"""

from __future__ import annotations

import fcntl
import tempfile
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import pytest

pytest_plugins = ["tests.fixtures_sim", "tests.fixtures_ssh", "tests.fixtures_ui"]

TESTS = Path(__file__).resolve().parent / "tests"
UNMARKED_SLOW_S = 1.0
unmarked_slow: dict[str, float] = {}
HEAVY_FOLDERS = ("browser", "real", "kernels")
#: fixtures that run something on its own real clock: a test using one is in the realtime tier
REALTIME_FIXTURES = frozenset(
    {"sim_factory", "sim_chair", "link_factory", "ros_factory", "sshd_server", "remote_maps_dir"}
)


def is_heavy_path(path: Path) -> bool:
    """True for a test file under one of the heavy folders."""
    return path.resolve().is_relative_to(TESTS) and path.resolve().relative_to(TESTS).parts[0] in HEAVY_FOLDERS


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    browser_modules = set()
    for item in items:
        if is_heavy_path(item.path) or item.get_closest_marker("browser"):
            item.add_marker(pytest.mark.heavy)
        if item.get_closest_marker("browser"):
            browser_modules.add(item.path)
        if item.get_closest_marker("heavy") or REALTIME_FIXTURES & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.realtime)
    # stable: modules stay whole (module fixtures set up once) and keep their order within a tier
    items.sort(key=lambda item: item.path not in browser_modules)


@pytest.hookimpl(hookwrapper=True, tryfirst=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None) -> Iterator[None]:
    """A browser test waits for the other worker's browser test to end (outside pytest-timeout's
    clock: this wrapper is the outermost), so a stolen browser test never runs beside another."""
    workerinput = getattr(item.config, "workerinput", None)
    if workerinput is None or item.get_closest_marker("browser") is None:
        yield
        return
    lock = Path(tempfile.gettempdir()) / f"pmk-browser-tests-{workerinput['testrunuid']}.lock"
    with lock.open("a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


#: seconds spent per tier (setup + call + teardown, summed over workers): where `make test`'s time goes
tier_seconds: dict[str, float] = {}


def _tier(keywords: Mapping[str, Any]) -> str:
    if "browser" in keywords:
        return "browser (one at a time)"
    if "heavy" in keywords:
        return "heavy, not browser"
    if "realtime" in keywords:
        return "realtime (sim, ssh, bridges)"
    return "unit"


def pytest_runtest_logreport(report: pytest.TestReport) -> None:
    """Adds up each unmarked test's setup, call and teardown (on the controller under xdist too)."""
    tier = _tier(report.keywords)
    tier_seconds[tier] = tier_seconds.get(tier, 0.0) + report.duration
    if "slow" in report.keywords or "heavy" in report.keywords:
        return
    unmarked_slow[report.nodeid] = unmarked_slow.get(report.nodeid, 0.0) + report.duration


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter) -> None:
    """Names the tests that belong in the slow tier (a report, not a failure: a loaded machine is slow),
    and the time each tier took."""
    if tier_seconds:
        terminalreporter.write_sep("-", "test time per tier (s, summed over workers)")
        for tier, seconds in sorted(tier_seconds.items(), key=lambda kv: -kv[1]):
            terminalreporter.write_line(f"{seconds:8.1f}  {tier}")
    found = sorted((t, nodeid) for nodeid, t in unmarked_slow.items() if t > UNMARKED_SLOW_S)
    if found:
        terminalreporter.write_sep(
            "-", f"{len(found)} tests took over {UNMARKED_SLOW_S:.0f} s without @pytest.mark.slow"
        )
        for t, nodeid in reversed(found):
            terminalreporter.write_line(f"{t:6.2f} s  {nodeid}")
