"""A chair per classroom page (issue 26): the cap counted across kernels, and two pages' own chairs.

The two "pages" are two real kernels' worth of processes: each runs ``build_app()`` with
``PMK_CLASSROOM`` set (what a Voilà kernel of ``pmk demo --classroom`` does), so each starts its own
simulated chair in its own process; the test drives one through the real link and watches both.
"""

from __future__ import annotations

import json
import math
import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.classroom import CLASSROOM_ENV, ChairCap, ClassroomFull, default_max_chairs
from pmk_nb.classroom.cap import MIB_PER_PAGE, PAGES_PER_CORE
from pmk_nb.clock import VirtualClock
from tests.fixtures_sim import wait_until

REPO = Path(__file__).resolve().parents[2]
GIB = 1024**3

# a page's kernel: build the app as Voilà's kernel does, say which chair it got, live until stdin closes
KERNEL = """
import json, sys
from pmk_nb.ui.app import build_app
app = build_app()
ctx = getattr(app, "ctx", None)
if ctx is None:
    print(json.dumps({"refused": app.value}), flush=True)
else:
    p = ctx.profile()
    notes = [n.message for n in ctx.notifications]
    print(json.dumps({"port": p.port, "sftp": p.ssh_port, "config": str(ctx.config_dir), "notes": notes}), flush=True)
sys.stdin.read()
"""


def test_the_default_cap_follows_cores_and_memory() -> None:
    assert default_max_chairs(cores=2, memory=64 * GIB) == 2 * PAGES_PER_CORE  # CPU-bound: 10 on 2 cores
    by_memory = int(0.75 * 2 * GIB) // (MIB_PER_PAGE * 1024 * 1024)
    assert default_max_chairs(cores=16, memory=2 * GIB) == by_memory == 5  # memory-bound
    assert default_max_chairs(cores=1, memory=100 * 1024 * 1024) == 1  # never below one
    assert default_max_chairs() >= 1


@pytest.fixture
def sleepers() -> Iterator[list[subprocess.Popen[bytes]]]:
    procs: list[subprocess.Popen[bytes]] = []
    yield procs
    for p in procs:
        p.kill()
        p.wait()


def _sleeper(procs: list[subprocess.Popen[bytes]]) -> int:
    procs.append(subprocess.Popen(["sleep", "60"]))
    return procs[-1].pid


def test_the_cap_refuses_one_more_and_forgets_dead_kernels(
    tmp_path: Path, sleepers: list[subprocess.Popen[bytes]]
) -> None:
    cap = ChairCap(tmp_path, 2)
    a, b, c = (_sleeper(sleepers) for _ in range(3))
    cap.take(a)
    cap.take(b)
    cap.take(a)  # a kernel that holds a seat keeps it (no second seat, no refusal)
    with pytest.raises(ClassroomFull) as refused:
        cap.take(c)
    assert (refused.value.in_use, refused.value.max_chairs) == (2, 2)
    assert "2 of 2" in str(refused.value)
    # counted across kernels: a second ChairCap on the same folder (another kernel) sees the same seats
    assert set(ChairCap(tmp_path, 2).live()) == {a, b}
    sleepers[0].kill()
    sleepers[0].wait()  # kernel a died without giving its seat back
    cap.take(c)
    assert set(cap.live()) == {b, c}
    cap.note(c, ros_port=1234)
    assert cap.live()[c]["ros_port"] == 1234
    cap.release(b)
    assert set(cap.live()) == {c}
    assert json.loads((tmp_path / "chairs.json").read_text()).keys() == {str(c)}


def test_a_seat_is_dated_on_the_caps_clock(tmp_path: Path) -> None:
    clock = VirtualClock(start=1.7e9)
    cap = ChairCap(tmp_path, 2, clock=clock)
    cap.take(os.getpid())
    clock.advance(30.0)
    cap.take(os.getpid())  # a seat kept keeps its date
    assert cap.live()[os.getpid()]["since"] == 1.7e9


class Page:
    """One classroom kernel (``build_app`` with ``PMK_CLASSROOM``) as a child process."""

    def __init__(self, env: dict[str, str]) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-c", KERNEL], env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, cwd=REPO
        )
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        assert line, f"the classroom kernel ended without a word (exit {self.proc.poll()})"
        self.info: dict[str, Any] = json.loads(line)

    def end(self) -> None:
        if self.proc.poll() is None:
            assert self.proc.stdin is not None
            self.proc.stdin.close()  # the kernel ends normally: atexit stops its chair
            try:
                self.proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


@pytest.fixture(scope="module")
def classroom(tmp_path_factory: pytest.TempPathFactory) -> Any:
    from pmk_nb.cli.demo_classroom import prepare_classroom

    return prepare_classroom(tmp_path_factory.mktemp("class"), max_chairs=2)


def _page_env(classroom: Any) -> dict[str, str]:
    env = dict(classroom.env)
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _yaw(link: Any) -> float:
    odom = link.latest_odom()
    assert odom is not None
    return float(odom.theta)


@pytest.mark.slow
@pytest.mark.realtime  # two real page processes, each with its own simulated chair
def test_two_classroom_pages_have_their_own_chairs(classroom: Any) -> None:
    """Driving one page's chair leaves the other's still; the third page is refused; all end with their kernels."""
    from pmk_nb.chair.link import ChairLink
    from pmk_nb.drive import drive_for

    assert classroom.env[CLASSROOM_ENV].endswith("classroom.json")
    pages = [Page(_page_env(classroom)) for _ in range(2)]
    links: list[Any] = []
    try:
        one, two = (p.info for p in pages)
        assert "port" in one and "port" in two, (one, two)
        assert one["port"] != two["port"] and one["sftp"] != two["sftp"] and one["config"] != two["config"]
        assert "lower rates" in one["notes"][-1]  # the page says its chair is simulated at lower rates
        third = Page(_page_env(classroom))  # cap 2: refused with words, not a third chair
        third.end()
        assert "The class is full: 2 of 2" in third.info["refused"]
        assert set(classroom.cap.live()) == {p.proc.pid for p in pages}
        for info in (one, two):
            links.append(ChairLink("127.0.0.1", info["port"]))
            links[-1].connect(timeout=15.0)
            links[-1].start_streams()
        assert all(wait_until(lambda lk=lk: lk.latest_odom() is not None, 15.0) for lk in links)
        first = [(lk.latest_odom().x, lk.latest_odom().y, _yaw(lk)) for lk in links]
        # parked at the same spot, no patrol: nothing moves by itself
        assert math.dist(first[0][:2], first[1][:2]) < 1e-6
        time.sleep(1.5)
        assert math.dist(first[1][:2], (links[1].latest_odom().x, links[1].latest_odom().y)) < 1e-6
        assert drive_for(links[0], 0.0, 0.6, 2.0) is None  # turn on the spot: no wall in the way
        time.sleep(0.5)
        turned = abs(math.remainder(_yaw(links[0]) - first[0][2], math.tau))
        assert turned > 0.3, f"the driven chair turned only {turned:.2f} rad"
        still = links[1].latest_odom()
        assert (still.x, still.y, still.theta) == pytest.approx(first[1], abs=1e-6), "the other page's chair moved"
    finally:
        for lk in links:
            lk.close()
        for p in pages:
            p.end()
    assert classroom.cap.live() == {}  # seats given back
    assert not any((Path(classroom.settings.state_dir) / "pages").iterdir())  # page folders removed


def test_closing_a_classroom_page_stops_its_chair_and_frees_its_seat(classroom: Any) -> None:
    """The page gone (its app closed by the page watch) ends the chair even while the kernel lives on."""
    from pmk_nb.ui.classroom_page import classroom_context

    os.environ[CLASSROOM_ENV] = classroom.env[CLASSROOM_ENV]
    try:
        ctx = classroom_context(classroom.env["PMK_MAPS_DIR"])
    finally:
        del os.environ[CLASSROOM_ENV]
    assert ctx is not None and ctx.seat is not None
    port = ctx.seat.ros_port
    assert os.getpid() in classroom.cap.live()
    socket.create_connection(("127.0.0.1", port), timeout=5).close()
    ctx.close()
    assert os.getpid() not in classroom.cap.live()
    with pytest.raises(OSError):
        socket.create_connection(("127.0.0.1", port), timeout=2).close()
    assert not ctx.seat.config_dir.exists()


def test_a_classroom_page_draws_at_the_classroom_frame_cap_and_says_so(classroom: Any) -> None:
    """Ten pages share two cores (bench/soak_classroom.py): Home's live view is capped lower, in words too."""
    from pmk_nb.classroom.settings import LIVE_FPS
    from pmk_nb.ui.classroom_page import classroom_context
    from pmk_nb.ui.home.screen import HomeScreen
    from pmk_nb.ui.live.view import DEFAULT_FPS

    os.environ[CLASSROOM_ENV] = classroom.env[CLASSROOM_ENV]
    try:
        ctx = classroom_context(classroom.env["PMK_MAPS_DIR"])
    finally:
        del os.environ[CLASSROOM_ENV]
    assert ctx is not None
    try:
        home = HomeScreen(ctx)
        assert home.live.canvas_fps == LIVE_FPS < DEFAULT_FPS  # the loop ticks faster for the page's feed
        assert f"map redrawn at most {LIVE_FPS:g} times a second" in ctx.notifications[-1].message
        home.close()
    finally:
        ctx.close()


@pytest.mark.slow
def test_a_killed_kernels_page_folder_is_removed_by_the_next_seat(classroom: Any) -> None:
    pages = Path(classroom.settings.state_dir) / "pages"
    dead = subprocess.Popen(["true"])
    dead.wait()
    (pages / str(dead.pid)).mkdir(parents=True)  # a kernel killed before its atexit ran
    page = Page(_page_env(classroom))
    try:
        assert "port" in page.info
        assert not (pages / str(dead.pid)).exists()
    finally:
        page.end()
