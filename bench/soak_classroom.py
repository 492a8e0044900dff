"""Classroom load (issue 26): ten classroom pages at once on this machine, each with its own chair.

``pmk demo --classroom``'s world (kiosk page, served by Voilà as ``pmk demo`` serves it); ``--pages``
headless Chromium pages open one after the other and stay on Home with the live view running, each
page's kernel running its own simulated chair at the classroom rates the page states.  Then:

1. **Frames/s per page** over ``--seconds`` while every chair turns on the spot (the soak publishes
   its ``/cmd_vel`` at 10 Hz: a parked chair's page draws nothing new, the live view draws on change),
   counted in the page: the frames drawn on its busiest canvas (one per message; a frame composited
   more than once counts once), while psutil samples the CPU and memory of every kernel (its chair
   included: a thread of it), Voilà and Chromium.  The same for a shorter window first with every
   chair parked (what an idle class costs).
2. **Drive press -> chair moving**: page after page (``--reps`` rounds), Playwright presses the
   Home joystick (turn on the spot); a separate roslibpy client per chair (tests/drive_world.py's
   ``ChairWatch``) records that chair's /cmd_vel and odometry.  Press time is taken just before the
   mouse goes down; "command" is the first /cmd_vel on the page's own chair, "moving" its first
   odometry with a speed.  A press that moves nothing within 5 s counts as a miss (and as 5 s).
3. **Nothing left**: every page closes; 30 s later it counts live kernels, seats in the class's
   ``chairs.json``, chair ports still accepting connections and Voilà's child processes.

Goals (issue 26): every page >= 10 frames/s, p95 press -> moving <= 300 ms, nothing left after 30 s.
The machine's load average is written beside the numbers: on a shared machine they say how loaded
it was.  Writes ``bench/results-soak-classroom.md`` and merges it into ``bench/results.md``.

Usage: python bench/soak_classroom.py [--pages N] [--seconds S] [--reps R] [--trace FILE]   (``make soak``)
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT)]

import psutil  # noqa: E402

from bench.soak import CHROMIUM, CHROMIUM_ARGS, VIEWPORT  # noqa: E402
from pmk_nb.classroom.settings import LIVE_FPS, ODOM_RATE, RAYS, SCAN_RATE  # noqa: E402
from pmk_nb.cli.bench import merge_results  # noqa: E402
from pmk_nb.cli.demo_classroom import Classroom, prepare_classroom  # noqa: E402
from pmk_nb.fileio import atomic_write  # noqa: E402
from pmk_nb.serve.procs import free_port, stop_process, wait_for_port  # noqa: E402
from pmk_nb.serve.voila import voila_command, write_dashboard_notebook  # noqa: E402
from pmk_nb.ui import KIOSK_ENV  # noqa: E402
from tests.drive_world import ChairWatch  # noqa: E402
from tests.page_probes import kernels  # noqa: E402

OUT = "results-soak-classroom.md"
MIB = 1024 * 1024
OPEN_WAIT_MS = 300_000  # one page on a loaded machine: Voilà runs the notebook, the kernel starts its chair
MISS_S = 5.0  # a press that moves nothing within this counts as a miss
AFTER_CLOSE_S = 30.0
GOAL_FPS, GOAL_P95_MS = 10.0, 300.0
PARKED_S = 10.0  # the parked window
TURN_W = 0.4  # rad/s: every chair turns on the spot during the frames window
TURN_HZ = 10.0  # its /cmd_vel rate per chair
#: Seconds between the first /cmd_vel and counting: every chair turning and every page drawing, so the
#: window measures the steady state, not the chairs starting
SETTLE_S = 1.5
#: Frames drawn, counted in the page: clears of its busiest canvas, clears in one run of code (until
#: its microtasks) counting once: ipycanvas clears the composite canvas and the one on screen for a
#: frame's message, more than once when it composites a frame twice (a timer reset instead ran late on
#: a loaded page and missed frames); ``__pmkClears`` counts every clear (composites).
FRAME_COUNTER_JS = """
window.__pmkFrames = 0; window.__pmkClears = 0;
const _clearRect = CanvasRenderingContext2D.prototype.clearRect;
CanvasRenderingContext2D.prototype.clearRect = function (...args) {
  const c = this.canvas;
  c.__pmkAll = (c.__pmkAll || 0) + 1;
  if (!c.__pmkInTask) {
    c.__pmkInTask = true;
    queueMicrotask(() => { c.__pmkInTask = false; });
    c.__pmkClears = (c.__pmkClears || 0) + 1;
  }
  if (c.__pmkClears > window.__pmkFrames) { window.__pmkFrames = c.__pmkClears; window.__pmkClears = c.__pmkAll; }
  return _clearRect.apply(this, args);
};
"""


@dataclass
class Student:
    """One page and, once a press has shown which one it is, its chair's watch."""

    page: Any
    centre: tuple[float, float, float] | None = None  # None: the page never came up (nothing to drive)
    watch: ChairWatch | None = None
    frames0: int = 0
    clears0: int = 0
    read0: float = 0.0


@dataclass
class Results:
    pages: int
    fps: list[float] = field(default_factory=list)
    fps_parked: list[float] = field(default_factory=list)
    clears_per_frame: float = float("nan")
    cmd_ms: list[float] = field(default_factory=list)
    moving_ms: list[float] = field(default_factory=list)
    misses: int = 0
    usage: dict[str, float] = field(default_factory=dict)
    usage_parked: dict[str, float] = field(default_factory=dict)
    left: dict[str, int] = field(default_factory=dict)
    load: list[tuple[str, tuple[float, float, float]]] = field(default_factory=list)
    window_s: float = 0.0
    open_s: float = 0.0
    not_live: int = 0  # pages that did not reach Live within OPEN_WAIT_MS


def pct(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))] if ordered else float("nan")


def _frames(page: Any) -> tuple[int, int, float]:
    """(frames, clears) of the page's busiest canvas, and the page's own clock (s) when it counted them.

    The rate is taken between two such readings on the page's clock: the harness's clock also counts
    the time a reading takes to come back, which on a loaded machine made the first page read look
    10 % slower than the rest, whichever page it was (tried with the reading order reversed)."""
    try:
        got = page.evaluate("[window.__pmkFrames || 0, window.__pmkClears || 0, performance.now() / 1000]")
        return int(got[0]), int(got[1]), float(got[2])
    except Exception:  # a page that lost its kernel and reloaded: count from zero
        return 0, 0, math.nan


def _ready(page: Any) -> tuple[float, float, float]:
    """Live on Home, the joystick out; the pad's centre and radius."""
    # the info panel stays hidden until Details opens it: attached is enough
    page.locator(".pmk-home-info-state", has_text="Live").wait_for(state="attached", timeout=OPEN_WAIT_MS)
    page.locator(".pmk-drive-toggle").click()
    page.wait_for_function("() => document.querySelector('.pmk-drive-pad[data-pmk-bound]') !== null")
    pad = page.locator(".pmk-drive-pad")
    pad.wait_for(state="visible", timeout=OPEN_WAIT_MS)  # bound before it is laid out: no box yet
    box = pad.bounding_box()
    assert box is not None, "the drive pad has no box"
    return box["x"] + box["width"] / 2, box["y"] + box["height"] / 2, box["width"] / 2


def _sample(groups: dict[str, list[psutil.Process]]) -> dict[str, tuple[float, float]]:
    out = {}
    for name, procs in groups.items():
        cpu = rss = 0.0
        for p in procs:
            with contextlib.suppress(psutil.Error):
                cpu += p.cpu_percent(None)
                rss += p.memory_info().rss / MIB
        out[name] = (cpu, rss)
    return out


class Turning:
    """Every chair turns on the spot: ``/cmd_vel`` at 10 Hz on each (the simulator stops 0.5 s after the last)."""

    def __init__(self, watches: list[ChairWatch]) -> None:
        import roslibpy

        self.topics = [roslibpy.Topic(w.ros, "/cmd_vel", "geometry_msgs/Twist") for w in watches]
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)

    def _twist(self, w: float) -> Any:
        import roslibpy

        return roslibpy.Message({"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": w}})

    def _run(self) -> None:
        while not self.stop.wait(1.0 / TURN_HZ):
            for t in self.topics:
                with contextlib.suppress(Exception):
                    t.publish(self._twist(TURN_W))
        for t in self.topics:
            with contextlib.suppress(Exception):
                t.publish(self._twist(0.0))

    def __enter__(self) -> Turning:
        self.thread.start()
        time.sleep(SETTLE_S)  # every chair turning (and every page drawing) before the frames are counted
        return self

    def __exit__(self, *_exc: object) -> None:
        self.stop.set()
        self.thread.join(5.0)
        time.sleep(1.0)  # parked again before the presses


def measure_frames(
    students: list[Student], voila: psutil.Process, seconds: float, res: Results, usage: dict[str, float]
) -> list[float]:
    """Frames/s of every page over ``seconds``, with CPU and memory per kernel, Voilà and Chromium into ``usage``."""
    ks = kernels(voila)
    chromium = [p for p in psutil.Process().children(recursive=True) if "chrom" in p.name().lower()]
    groups = {"kernels": ks, "voila": [voila], "chromium": chromium, "harness": [psutil.Process()]}
    _sample(groups)  # primes cpu_percent
    for s in students:
        s.frames0, s.clears0, s.read0 = _frames(s.page)  # each page's frames over its own interval
    t0 = time.monotonic()
    samples: list[dict[str, tuple[float, float]]] = []
    while time.monotonic() - t0 < seconds:
        time.sleep(min(5.0, max(0.1, seconds - (time.monotonic() - t0))))
        samples.append(_sample(groups))
    window = time.monotonic() - t0
    counts = [_frames(s.page) for s in students]
    spans = [t - s.read0 if t > s.read0 else window for (_f, _c, t), s in zip(counts, students, strict=True)]
    frames = [f - s.frames0 for (f, _c, _t), s in zip(counts, students, strict=True)]
    clears = [c - s.clears0 for (_f, c, _t), s in zip(counts, students, strict=True)]
    if sum(frames) > 0:
        res.clears_per_frame = sum(clears) / sum(frames)
    n = max(1, len(ks))
    for name in groups:
        cpu = statistics.mean(x[name][0] for x in samples)
        rss = max(x[name][1] for x in samples)
        per = n if name not in ("voila", "harness") else 1
        usage[f"{name} CPU %"] = cpu / per
        usage[f"{name} RSS MiB"] = rss / per
    usage["kernels counted"] = len(ks)
    usage["window s"] = window
    return [f / span for f, span in zip(frames, spans, strict=True)]


def _press(s: Student, watches: list[ChairWatch], res: Results) -> None:
    """One press-hold-release on ``s``'s stick; the first press finds its chair among ``watches``."""
    assert s.centre is not None
    cx, cy, r = s.centre
    s.page.bring_to_front()  # each student's own screen has the focus (the page lets go on a blur)
    s.page.mouse.move(cx + 0.97 * r, cy)  # inside the pad at its right edge: turn on the spot, no wall near
    pressed = time.monotonic()
    s.page.mouse.down()
    s.page.mouse.move(cx + 1.3 * r, cy, steps=2)
    mine = [s.watch] if s.watch is not None else watches
    deadline = pressed + MISS_S
    moved: tuple[float, ChairWatch] | None = None
    while moved is None and time.monotonic() < deadline:
        hits = [(t, w) for w in mine if (t := w.first(pressed, w.moving, 0.0)) is not None]
        moved = min(hits, key=lambda h: h[0]) if hits else None
        if moved is None:
            time.sleep(0.02)
    s.page.wait_for_timeout(300)
    s.page.mouse.up()
    if moved is None:
        with contextlib.suppress(Exception):
            status = s.page.locator(".pmk-drive-status").inner_text(timeout=2000)
            print(f"missed press; the page says: {status!r}", flush=True)
        res.misses += 1
        res.moving_ms.append(1000.0 * MISS_S)
        return
    s.watch = moved[1]
    res.moving_ms.append(1000.0 * moved[0])
    cmds = [c for c in s.watch.cmds_since(pressed) if c[2] != 0.0]
    if cmds:
        res.cmd_ms.append(1000.0 * (cmds[0][0] - pressed))
    s.watch.first(time.monotonic(), s.watch.still, 3.0)  # parked again before the next page


def measure_drive(students: list[Student], watches: list[ChairWatch], reps: int, res: Results) -> None:
    for _ in range(reps):
        for s in students:
            if s.centre is not None:
                _press(s, watches, res)


def _accepts(port: int) -> bool:
    with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", port), timeout=1.0):
        return True
    return False


def measure_left(browser: Any, room: Classroom, voila: psutil.Process, res: Results) -> None:
    """Close every page; 30 s later count what is still there."""
    ports = [int(e["ros_port"]) for e in room.cap.live().values() if "ros_port" in e]
    for ctx in list(browser.contexts):
        ctx.close()
    time.sleep(AFTER_CLOSE_S)
    res.left = {
        "kernels": len(kernels(voila)),
        "seats in chairs.json": len(room.cap.live()),
        "chair ports answering": sum(_accepts(p) for p in ports),
        "processes under Voilà": sum(1 for p in voila.children(recursive=True) if p.status() != psutil.STATUS_ZOMBIE),
    }


def _open(browser: Any, url: str, res: Results) -> list[Student]:
    students = []
    t0 = time.monotonic()
    for i in range(res.pages):  # one after the other, like students arriving
        page = browser.new_context(viewport=VIEWPORT).new_page()
        page.set_default_timeout(OPEN_WAIT_MS)
        page.add_init_script(FRAME_COUNTER_JS)
        try:
            page.goto(url, wait_until="commit", timeout=OPEN_WAIT_MS)
            students.append(Student(page, _ready(page)))
        except Exception as err:  # a page that never came up counts (0 frames/s, no presses); go on
            students.append(Student(page))
            res.not_live += 1
            print(f"page {i + 1} not live: {(str(err) or type(err).__name__).splitlines()[0]}", flush=True)
        print(f"page {i + 1} after {time.monotonic() - t0:.0f} s, load {os.getloadavg()[0]:.1f}", flush=True)
    res.open_s = time.monotonic() - t0
    return students


@contextlib.contextmanager
def browser_trace(browser: Any, page: Any, path: Path | None) -> Iterator[None]:
    """A Chromium trace (chrome://tracing, Perfetto) of the block into ``path``; nothing when None.

    Where a page's frame goes: the renderer's main thread (the frame's message, ipycanvas's
    commands and composites), its compositor and the display compositor (``viz``)."""
    if path is None:
        yield
        return
    categories = ["devtools.timeline", "disabled-by-default-devtools.timeline", "toplevel", "cc", "viz", "blink"]
    browser.start_tracing(page=page, categories=categories)
    try:
        yield
    finally:
        path.write_bytes(browser.stop_tracing())


def run(pages: int, seconds: float, reps: int, trace: Path | None = None) -> Results:
    from playwright.sync_api import sync_playwright

    res = Results(pages)
    res.load.append(("start", os.getloadavg()))
    with tempfile.TemporaryDirectory(prefix="pmk-soak-classroom-") as tmp:
        room = prepare_classroom(Path(tmp) / "demo", max_chairs=pages)
        room.env[KIOSK_ENV] = "1"  # as `pmk demo --classroom` serves it
        # compiled modules kept for the run, as an installed package has them (with PYTHONDONTWRITEBYTECODE
        # every kernel compiled pmk_nb again: 1 s of CPU per page start, 0.96 of its 4.8 s build)
        room.env.pop("PYTHONDONTWRITEBYTECODE", None)
        room.env["PYTHONPYCACHEPREFIX"] = str(Path(tmp) / "pycache")
        # the kernels run this tree's pmk_nb (a second checkout's soak measured the installed one)
        room.env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), room.env.get("PYTHONPATH", "")) if p)
        port = free_port()
        notebook = write_dashboard_notebook(Path(tmp) / "served")
        log = (Path(tmp) / "voila.log").open("wb")
        server = subprocess.Popen(
            voila_command(notebook, port=port), env=room.env, cwd=notebook.parent, stdout=log, stderr=subprocess.STDOUT
        )
        try:
            wait_for_port("127.0.0.1", port, server, "Voilà", 120.0)
            voila = psutil.Process(server.pid)
            with sync_playwright() as pw:
                browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
                try:
                    students = _open(browser, f"http://127.0.0.1:{port}/", res)
                    res.load.append(("pages open", os.getloadavg()))
                    ports = sorted(int(e["ros_port"]) for e in room.cap.live().values() if "ros_port" in e)
                    # connected only: the watches subscribe for the presses, after the frames windows,
                    # so that the harness's own watching does not load the chairs it measures
                    watches = [ChairWatch(p, listen=False) for p in ports]
                    try:
                        res.fps_parked = measure_frames(students, voila, PARKED_S, res, res.usage_parked)
                        with Turning(watches), browser_trace(browser, students[0].page, trace):
                            res.fps = measure_frames(students, voila, seconds, res, res.usage)
                        res.window_s = res.usage["window s"]
                        for w in watches:
                            w.listen()
                        res.load.append(("after the frames window", os.getloadavg()))
                        measure_drive(students, watches, reps, res)
                    finally:
                        for w in watches:
                            w.close()
                    res.load.append(("after driving", os.getloadavg()))
                    measure_left(browser, room, voila, res)
                finally:
                    browser.close()
        finally:
            stop_process(server)
            log.close()
    return res


def verdicts(res: Results) -> dict[str, bool]:
    return {
        "frames": bool(res.fps) and min(res.fps) >= GOAL_FPS and not res.not_live,
        "drive": pct(res.moving_ms, 0.95) <= GOAL_P95_MS,
        "left": not any(res.left.values()),
    }


def write(res: Results, reps: int) -> bool:
    ok = verdicts(res)
    mark = {True: "met", False: "**not met**"}
    cpus = os.cpu_count()
    u, up = res.usage, res.usage_parked
    fps = sorted(res.fps)
    lines = [
        "## Soak: classroom (a chair per page)",
        "",
        f"`bench/soak_classroom.py` (`make soak`; `--pages {res.pages} --seconds {res.window_s:.0f} --reps {reps}`): "
        f"{res.pages} classroom pages (`pmk demo --classroom`, kiosk, headless Chromium "
        f"{VIEWPORT['width']}x{VIEWPORT['height']}) on Home with the live view, each page's kernel running its "
        f"own chair at the classroom rates the page states (odometry {ODOM_RATE:g} Hz, laser {SCAN_RATE:g} Hz, "
        f"{RAYS} rays, live view capped at {LIVE_FPS:g} frames/s), all on this {cpus}-core machine. Pages opened one "
        f"after the other in {res.open_s:.0f} s; {res.not_live} did not reach Live within {OPEN_WAIT_MS / 1000:.0f} s.",
        "",
        "Load average (1, 5, 15 min) of the machine, shared with other jobs: "
        + "; ".join(f"{when} {a:.1f} / {b:.1f} / {c:.1f}" for when, (a, b, c) in res.load)
        + ".",
        "",
        "| goal | measured | verdict |",
        "|---|---|---|",
        f"| every page >= {GOAL_FPS:g} frames/s (every chair turning) | min {fps[0]:.1f}, median "
        f"{statistics.median(fps):.1f}, max {fps[-1]:.1f} over {res.window_s:.0f} s | {mark[ok['frames']]} |",
        f"| press -> chair moving p95 <= {GOAL_P95_MS:g} ms | median {statistics.median(res.moving_ms):.0f} ms, "
        f"p95 {pct(res.moving_ms, 0.95):.0f} ms, max {max(res.moving_ms):.0f} ms ({len(res.moving_ms)} presses, "
        f"{res.misses} missed) | {mark[ok['drive']]} |",
        f"| nothing left {AFTER_CLOSE_S:.0f} s after the pages close | "
        + ", ".join(f"{k} {v}" for k, v in res.left.items())
        + f" | {mark[ok['left']]} |",
        "",
        "Press -> first /cmd_vel on the page's chair: "
        + (
            f"median {statistics.median(res.cmd_ms):.0f} ms, p95 {pct(res.cmd_ms, 0.95):.0f} ms."
            if res.cmd_ms
            else "none seen."
        ),
        f"Frames/s per page, every chair turning: {', '.join(f'{f:.1f}' for f in res.fps)} "
        f"({res.clears_per_frame:.1f} clears of the busiest canvas per frame); every chair parked "
        f"({PARKED_S:.0f} s, drawn on change only): {', '.join(f'{f:.1f}' for f in res.fps_parked)}.",
        "",
        "Per page during the frames windows (CPU in % of one core, psutil; RSS peak):",
        "",
        "| per page | CPU % turning | CPU % parked | RSS MiB |",
        "|---|---|---|---|",
        f"| kernel + its chair (mean of {u['kernels counted']:.0f}) | {u['kernels CPU %']:.1f} "
        f"| {up.get('kernels CPU %', float('nan')):.1f} | {u['kernels RSS MiB']:.0f} |",
        f"| Chromium (all its processes / pages) | {u['chromium CPU %']:.1f} "
        f"| {up.get('chromium CPU %', float('nan')):.1f} | {u['chromium RSS MiB']:.0f} |",
        f"| Voilà server (whole, all pages) | {u['voila CPU %']:.1f} | {up.get('voila CPU %', float('nan')):.1f} "
        f"| {u['voila RSS MiB']:.0f} |",
        f"| this harness (whole: it turns every chair, {TURN_HZ:g} Hz each) | {u['harness CPU %']:.1f} "
        f"| {up.get('harness CPU %', float('nan')):.1f} | {u['harness RSS MiB']:.0f} |",
        "",
    ]
    atomic_write(HERE / OUT, "\n".join(lines))
    merge_results(HERE)
    print("\n".join(lines))
    return all(ok.values())


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pages", type=int, default=10, help="classroom pages at once (default 10)")
    parser.add_argument("--seconds", type=float, default=60.0, help="frames window (default 60)")
    parser.add_argument("--trace", type=Path, help="write a Chromium trace of the turning window here")
    parser.add_argument("--reps", type=int, default=3, help="presses per page (default 3)")
    args = parser.parse_args(argv)
    res = run(max(1, args.pages), max(5.0, args.seconds), max(1, args.reps), args.trace)
    ok = write(res, args.reps)
    print("classroom soak:", "every goal met" if ok else "a goal not met: see the table", flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
