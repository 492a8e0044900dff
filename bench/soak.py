"""Soak: a day of kiosk tablets in ten minutes -- nothing may grow without bound.

Ten kiosk pages (headless Chromium, Playwright) stay on Home with the live view running for
``--minutes`` (default 10) against the simulated chair at 50 Hz odometry and 40 Hz 1080-ray scans,
served by Voilà exactly as ``pmk dashboard --kiosk`` serves it.  Pages reload at random (each at
most once per :data:`MIN_RELOAD_GAP_S`, with probability :data:`RELOAD_P` per check).  Every
:data:`SAMPLE_S` seconds, measured from the operating system (tests/page_probes.py): kernels and
their memory, Voilà's memory, open file descriptors (Voilà, kernels, simulator), chair
connections.  Frames drawn are counted in each page (calls that clear its busiest canvas: one per
live-view frame).

Verdict per series: the mean of the last third of the run against the mean of the first third
(after :data:`WARMUP_S`) and the least-squares slope; a series passes when the growth stays within
its tolerance.  Writes ``bench/results-soak.md`` and merges it into ``bench/results.md``.

Usage: python bench/soak.py [--minutes M] [--pages N]     (``make soak``; not part of ``make test``)
"""

from __future__ import annotations

import argparse
import contextlib
import random
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT)]

from pmk_nb.cli.bench import merge_results  # noqa: E402
from pmk_nb.cli.demo_setup import prepare_demo  # noqa: E402
from pmk_nb.fileio import atomic_write  # noqa: E402
from pmk_nb.serve.procs import free_port, stop_process, wait_for_port  # noqa: E402
from pmk_nb.serve.voila import voila_command, write_dashboard_notebook  # noqa: E402
from pmk_nb.serve.voila_kernels import RENDERED_PAGE_WITHIN, SLOW_CONNECT_FACTOR  # noqa: E402
from pmk_nb.ui import KIOSK_ENV  # noqa: E402
from tests.page_probes import chair_connections, kernels, open_fds, rss_mb, voila_process  # noqa: E402

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--headless",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-renderer-backgrounding",
    "--disable-background-timer-throttling",
]
SIM_ARGS = ["--odom-rate", "50", "--scan-rate", "40", "--rays", "1080"]
VIEWPORT = {"width": 1280, "height": 800}
SAMPLE_S = 10.0
WARMUP_S = 60.0
DEFAULT_OUT = "results-soak.md"
RELOAD_P = 0.08  # per page per check (every SAMPLE_S): about one reload per page every 2 min
MIN_RELOAD_GAP_S = 60.0
OPEN_WAIT_MS = 30_000  # per page at the start: then the next tablet is switched on anyway
PAGE_LOAD_MS = 600_000  # Voilà runs the notebook before it answers; the 2-core machine may be shared
# Counts the clears of each canvas; the busiest canvas is the live view's moving layer (one per frame).
FRAME_COUNTER_JS = """
window.__pmkFrames = 0;
const _clearRect = CanvasRenderingContext2D.prototype.clearRect;
CanvasRenderingContext2D.prototype.clearRect = function (...args) {
  const c = this.canvas;
  c.__pmkClears = (c.__pmkClears || 0) + 1;
  if (c.__pmkClears > window.__pmkFrames) window.__pmkFrames = c.__pmkClears;
  return _clearRect.apply(this, args);
};
"""


@dataclass
class Series:
    """One measured quantity over time and how much it may grow (absolute, or relative to the start)."""

    name: str
    unit: str
    abs_tol: float
    rel_tol: float = 0.0
    points: list[tuple[float, float]] = field(default_factory=list)

    def verdict(self, warmup: float) -> dict[str, Any]:
        pts = [(t, v) for t, v in self.points if t >= warmup] or self.points
        third = max(1, len(pts) // 3)
        first = sum(v for _, v in pts[:third]) / third
        last = sum(v for _, v in pts[-third:]) / third
        slope = _slope(pts) * 60.0
        allowed = max(self.abs_tol, self.rel_tol * abs(first))
        ok = last - first <= allowed
        values = [v for _, v in pts]
        return {
            "first": first,
            "last": last,
            "slope": slope,
            "allowed": allowed,
            "ok": ok,
            "min": min(values),
            "max": max(values),
        }


def _slope(pts: list[tuple[float, float]]) -> float:
    if len(pts) < 2:
        return 0.0
    n = len(pts)
    mt = sum(t for t, _ in pts) / n
    mv = sum(v for _, v in pts) / n
    den = sum((t - mt) ** 2 for t, _ in pts)
    return sum((t - mt) * (v - mv) for t, v in pts) / den if den else 0.0


@dataclass
class Page:
    """One tablet: its Playwright page, frames drawn before its last reload, reload times."""

    page: Any
    frames_before: int = 0
    reloads: int = 0
    last_reload: float = 0.0
    failed_loads: int = 0

    def frames_now(self) -> int:
        try:
            return int(self.page.evaluate("window.__pmkFrames || 0"))
        except Exception:  # mid-reload
            return 0

    def reload(self, now: float) -> None:
        self.frames_before += self.frames_now()
        self.reloads += 1
        self.last_reload = now
        try:  # "commit": do not wait while Voilà runs the notebook; the page comes up by itself
            self.page.reload(wait_until="commit", timeout=PAGE_LOAD_MS)
        except Exception as err:  # a loaded machine: count it, keep soaking
            self.failed_loads += 1
            print(f"reload failed: {str(err).splitlines()[0]}", flush=True)


def _log_page_watch(n: int) -> Any:
    def on_console(msg: Any) -> None:
        if "pmk page watch" in msg.text:
            print(f"page {n}: {msg.text}", flush=True)

    return on_console


def _log_navigation(n: int) -> Any:
    def on_nav(frame: Any) -> None:
        if frame.parent_frame is None:
            print(f"page {n}: navigated at {time.strftime('%X')}", flush=True)

    return on_nav


def sample(voila: Any, sim_pid: int, ros_port: int, t: float, series: dict[str, Series]) -> str:
    import psutil

    ks = kernels(voila)
    kernel_rss = []
    kernel_fds = []
    for k in ks:
        with contextlib.suppress(psutil.Error):
            kernel_rss.append(rss_mb(k))
            kernel_fds.append(open_fds(k))
    sim = psutil.Process(sim_pid)
    values = {
        "kernels": len(ks),
        "chair connections": chair_connections(sim_pid, ros_port),
        "Voilà RSS": rss_mb(voila),
        "kernels RSS (sum)": sum(kernel_rss),
        "kernel RSS (max)": max(kernel_rss, default=0.0),
        "simulator RSS": rss_mb(sim),
        "Voilà fds": open_fds(voila),
        "kernel fds (max)": max(kernel_fds, default=0),
        "simulator fds": open_fds(sim),
    }
    for name, value in values.items():
        series[name].points.append((t, float(value)))
    return ", ".join(f"{n} {v:.0f}" for n, v in values.items())


def new_series() -> dict[str, Series]:
    mb, fds, count = "MB", "fds", ""
    return {
        s.name: s
        for s in [
            Series("kernels", count, 1.0),
            Series("chair connections", count, 1.0),
            Series("Voilà RSS", mb, 15.0, 0.10),
            Series("kernels RSS (sum)", mb, 60.0, 0.10),
            Series("kernel RSS (max)", mb, 15.0, 0.10),
            Series("simulator RSS", mb, 15.0, 0.10),
            Series("Voilà fds", fds, 10.0, 0.10),
            Series("kernel fds (max)", fds, 5.0),
            Series("simulator fds", fds, 5.0),
        ]
    }


def run(minutes: float, n_pages: int, seed: int) -> tuple[dict[str, Series], list[Page], float, list[str]]:
    from playwright.sync_api import sync_playwright

    rng = random.Random(seed)
    series = new_series()
    notes: list[str] = []
    with tempfile.TemporaryDirectory(prefix="pmk-soak-") as tmp_name:
        tmp = Path(tmp_name)
        world = prepare_demo(tmp / "demo", sim_args=SIM_ARGS)
        port = free_port()
        notebook = write_dashboard_notebook(tmp / "kiosk")
        env = {**world.env, KIOSK_ENV: "1"}
        log = (tmp / "voila.log").open("wb")
        server = subprocess.Popen(
            voila_command(notebook, port=port), env=env, cwd=notebook.parent, stdout=log, stderr=subprocess.STDOUT
        )
        try:
            wait_for_port("127.0.0.1", port, server, "Voilà", 120.0)
            voila = voila_process(port)
            url = f"http://127.0.0.1:{port}/"
            with sync_playwright() as pw:
                browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
                try:
                    pages = []
                    for i in range(n_pages):  # one after the other, like tablets switched on
                        page = browser.new_context(viewport=VIEWPORT).new_page()
                        page.add_init_script(FRAME_COUNTER_JS)
                        page.on("console", _log_page_watch(i + 1))
                        page.on("framenavigated", _log_navigation(i + 1))
                        page.goto(url, wait_until="commit", timeout=PAGE_LOAD_MS)
                        with contextlib.suppress(Exception):  # a slow page still counts (fewer frames)
                            page.wait_for_selector(".pmk-home-info-state", timeout=OPEN_WAIT_MS)
                        print(f"page {i + 1} opened", flush=True)
                        pages.append(Page(page))
                    t0 = time.monotonic()
                    for p in pages:  # count from here: frames drawn while the other pages loaded are not in the run
                        p.frames_before = -p.frames_now()
                    duration = minutes * 60.0
                    while (t := time.monotonic() - t0) < duration:
                        line = sample(voila, world.sim.pid, world.ros_port, t, series)
                        print(f"[{t:5.0f} s] {line}", flush=True)
                        for p in pages:
                            if t - p.last_reload >= MIN_RELOAD_GAP_S and rng.random() < RELOAD_P:
                                p.reload(t)
                        time.sleep(max(0.0, SAMPLE_S - (time.monotonic() - t0 - t)))
                    elapsed = time.monotonic() - t0
                    for p in pages:
                        p.frames_before += p.frames_now()
                    for p in pages:
                        p.page.context.close()
                    # after the last page closes, everything must go back to nothing
                    deadline = time.monotonic() + 30.0
                    while time.monotonic() < deadline and (
                        kernels(voila) or chair_connections(world.sim.pid, world.ros_port)
                    ):
                        time.sleep(0.5)
                    notes.append(
                        f"{time.monotonic() - deadline + 30.0:.1f} s after closing all pages: "
                        f"{len(kernels(voila))} kernels, "
                        f"{chair_connections(world.sim.pid, world.ros_port)} chair connections left"
                    )
                finally:
                    browser.close()
        finally:
            stop_process(server)
            world.stop()
            log.close()
            voila_log = (tmp / "voila.log").read_text(errors="replace")
            notes.append(
                f"Voilà log: {voila_log.count('Discarding')} 'Discarding ... buffered messages' lines, "
                f"{voila_log.count('Timeout waiting for IOPub')} 'Timeout waiting for IOPub', "
                f"{voila_log.count('Kernel started')} kernels started, "
                f"{voila_log.count('its page is gone;')} shut down after their page closed, "
                f"{voila_log.count('its page stopped answering;')} after their page stopped pinging"
            )
            notes.append(render_to_connect(voila_log))
    return series, pages, elapsed, notes


def render_to_connect(voila_log: str) -> str:
    """How long pages took to connect after their kernel's render: the manager's grace must cover it."""
    waits = sorted(float(m) for m in re.findall(r"its page connected ([0-9.]+) s after the render", voila_log))
    late = len(set(re.findall(r"Kernel does not exist: ([0-9a-f-]+)", voila_log)))
    if not waits:
        return f"no page connected after a logged render; {late} pages came after their kernel was ended"
    return (
        f"page connected after its kernel's render: {len(waits)} pages, median {waits[len(waits) // 2]:.1f} s, "
        f"max {waits[-1]:.1f} s (grace: {RENDERED_PAGE_WITHIN:.0f} s, or {SLOW_CONNECT_FACTOR:.0f} x the slowest "
        f"recent wait); {late} pages came after their kernel was ended (a page closed mid-load never comes)"
    )


def write(
    series: dict[str, Series], pages: list[Page], elapsed: float, notes: list[str], n: int, out: str = DEFAULT_OUT
) -> bool:
    verdicts = {name: s.verdict(WARMUP_S) for name, s in series.items()}
    command = "`make soak`" if out == DEFAULT_OUT else f"`--minutes {elapsed / 60:.0f} --out {out}`"
    lines = [
        "## Soak (kiosk pages all day)" if out == DEFAULT_OUT else f"## Soak, {elapsed / 60:.0f} min",
        "",
        f"`bench/soak.py` ({command}): {n} kiosk pages (headless Chromium, {VIEWPORT['width']}x"
        f"{VIEWPORT['height']}) on Home with the live view, {elapsed / 60:.1f} min against the simulated chair "
        "(50 Hz odometry, 40 Hz 1080-ray scans, patrolling), served by Voilà as `pmk dashboard --kiosk`. "
        f"Pages reload at random (each at most once a minute). Sampled every {SAMPLE_S:.0f} s from the OS "
        f"(psutil). Verdict: mean of the last third against the first third (after {WARMUP_S:.0f} s warm-up); "
        "passes when the growth is within the allowed margin.",
        "",
        "| series | first third | last third | min / max | slope per min | allowed growth | bounded |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, v in verdicts.items():
        unit = series[name].unit
        lines.append(
            f"| {name} | {v['first']:.1f} {unit} | {v['last']:.1f} {unit} | {v['min']:.0f} / {v['max']:.0f} "
            f"| {v['slope']:+.2f} | {v['allowed']:.1f} | {'pass' if v['ok'] else '**FAIL**'} |"
        )
    per_page = [(p.frames_before, p.reloads) for p in pages]
    fps = [f / elapsed for f, _ in per_page]
    lines += [
        "",
        "Frames drawn per page (whole run, reloads included; frames/s = frames / run time):",
        "",
        "| page | frames drawn | frames/s | reloads | reloads that timed out |",
        "|---|---|---|---|---|",
        *[
            f"| {i + 1} | {f} | {f / elapsed:.1f} | {r} | {p.failed_loads} |"
            for i, ((f, r), p) in enumerate(zip(per_page, pages, strict=True))
        ],
        "",
        f"Frames/s per page: min {min(fps):.1f}, median {sorted(fps)[len(fps) // 2]:.1f}, max {max(fps):.1f} "
        f"({n} pages share the 2-core machine with the simulator and Voilà); reloads {sum(r for _, r in per_page)}.",
        "",
        *[f"- {note}" for note in notes],
        "",
    ]
    atomic_write(HERE / out, "\n".join(lines))
    merge_results(HERE)
    print("\n".join(lines))
    return all(v["ok"] for v in verdicts.values())


def _results_name(value: str) -> str:
    """A results file name in bench/ that results.md picks up: results-soak*.md, no folders."""
    if "/" in value or not (value.startswith("results-soak") and value.endswith(".md")):
        raise argparse.ArgumentTypeError(f"{value!r}: name a file results-soak<something>.md (it stays in bench/)")
    return value


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=10.0, help="how long the pages run (default 10)")
    parser.add_argument("--pages", type=int, default=10, help="kiosk pages at once (default 10)")
    parser.add_argument("--seed", type=int, default=10, help="seed of the random reloads")
    parser.add_argument(
        "--out",
        type=_results_name,
        default=DEFAULT_OUT,
        help=f"results file in bench/, merged into results.md (default {DEFAULT_OUT})",
    )
    args = parser.parse_args(argv)
    series, pages, elapsed, notes = run(args.minutes, args.pages, args.seed)
    ok = write(series, pages, elapsed, notes, args.pages, args.out)
    print("soak:", "every series bounded" if ok else "a series grew: see the table", flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
