"""Drive latencies through a real browser: press -> first command on the chair, release -> chair stopped.

The real path end to end: headless Chromium shows the dashboard served by Voilà; Playwright holds
the joystick with the mouse; the page posts the stick to the kernel; the kernel's drive session
publishes over the chair link (roslibpy) to the simulated chair (rosbridge v2, its own process,
50 Hz odometry). A separate roslibpy client (this process) watches the chair: the press time is
taken just before the mouse goes down, "first command" is the first /cmd_vel the bridge forwards
to it, "moving" the first odometry with a speed, "stopped" the first odometry at rest after the
mouse went up. Each repetition holds for 1 s; a hold that the deadman cut short (a kernel that
fell behind by more than 200 ms on this shared machine) is counted and repeated.

Usage: python bench/bench_drive.py [--quick] [--reps N]   -> bench/results-drive.md
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the browser tests' world: tests/drive_world.py

from tests.drive_world import ChairWatch, drive_world  # noqa: E402

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--headless", "--disable-gpu", "--no-first-run", "--disable-background-networking"]


def pct(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


def run(reps: int) -> dict[str, list[float] | int]:
    from playwright.sync_api import sync_playwright

    out: dict[str, list[float] | int] = {"cmd": [], "moving": [], "stopped": [], "cut": 0, "lost": 0}
    with tempfile.TemporaryDirectory() as tmp, drive_world(Path(tmp)) as world:
        watch = ChairWatch(world.ros_port)
        try:
            with sync_playwright() as pw:
                browser = pw.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
                page = browser.new_page(viewport={"width": 1280, "height": 800})
                page.set_default_timeout(120_000)
                page.goto(world.url, wait_until="domcontentloaded")
                page.locator(".pmk-home-info-state", has_text="Live").wait_for(timeout=120_000)
                page.locator(".pmk-drive-toggle").click()
                page.wait_for_function("() => document.querySelector('.pmk-drive-pad[data-pmk-bound]') !== null")
                box = page.locator(".pmk-drive-pad").bounding_box()
                assert box is not None
                cx, cy, r = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2, box["width"] / 2
                tries = 0
                while len(out["stopped"]) < reps and tries < 3 * reps:  # type: ignore[arg-type]
                    tries += 1
                    if not one(page, watch, (cx, cy, r), out):
                        pad = page.locator(".pmk-drive-pad")
                        status = page.locator(".pmk-drive-status").inner_text() if pad.is_visible() else "(no stick)"
                        print(f"cut short; the page says: {status}", file=sys.stderr)
                        if not pad.is_visible():  # the page lost its kernel (page_lifecycle): start again
                            out["lost"] += 1  # type: ignore[operator]
                            page.reload()
                            page.locator(".pmk-home-info-state", has_text="Live").wait_for(timeout=120_000)
                            page.locator(".pmk-drive-toggle").click()
                            page.locator(".pmk-drive-pad").wait_for(state="visible", timeout=120_000)
                    page.wait_for_timeout(700)
                browser.close()
        finally:
            watch.close()
    return out


def one(page: object, watch: ChairWatch, centre: tuple[float, float, float], out: dict) -> bool:
    """One press-hold-release; False when the hold was cut short (nothing measured)."""
    cx, cy, r = centre
    page.mouse.move(cx, cy - 0.97 * r)  # type: ignore[attr-defined]  # inside the pad, near the top: ~full speed
    pressed = time.monotonic()
    page.mouse.down()  # type: ignore[attr-defined]
    moving = watch.first(pressed, watch.moving, 5.0)
    cmds = [c for c in watch.cmds_since(pressed) if c[1] != 0.0]
    page.wait_for_timeout(1000)  # type: ignore[attr-defined]
    if moving is None or not cmds or not watch.moving(*watch.odom[-1][1:]):
        out["cut"] += 1
        page.mouse.up()  # type: ignore[attr-defined]
        return False
    released = time.monotonic()
    page.mouse.up()  # type: ignore[attr-defined]
    stopped = watch.first(released, watch.still, 3.0)
    if stopped is None:
        out["cut"] += 1
        return False
    out["cmd"].append(cmds[0][0] - pressed)
    out["moving"].append(moving)
    out["stopped"].append(stopped)
    return True


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="5 repetitions")
    ap.add_argument("--reps", type=int, default=20)
    args = ap.parse_args()
    if not CHROMIUM.exists():
        print(f"{CHROMIUM} missing: apt-get install -y chromium", file=sys.stderr)
        return 1
    reps = 5 if args.quick else max(1, min(args.reps, 100))
    started = time.monotonic()
    res = run(reps)
    rows = []
    for key, label in (
        ("cmd", "press -> first command on the chair"),
        ("moving", "press -> chair moving (odometry)"),
        ("stopped", "release -> chair stopped (odometry)"),
    ):
        ms = [1000.0 * v for v in res[key]]  # type: ignore[union-attr]
        if ms:
            rows.append(f"| {label} | {len(ms)} | {statistics.median(ms):.0f} | {pct(ms, 0.95):.0f} | {max(ms):.0f} |")
    text = "\n".join(
        [
            "## Drive (joystick in Chromium -> Voilà kernel -> rosbridge -> simulated chair)",
            "",
            "`bench/bench_drive.py`: Playwright holds the Home joystick with the mouse for 1 s, then lets go; "
            "a separate roslibpy client watches /cmd_vel and the simulator's 50 Hz odometry. "
            "Targets: release -> stopped <= 500 ms; commands older than 200 ms are never sent.",
            "",
            "| measure | n | median ms | p95 ms | max ms |",
            "|---|---|---|---|---|",
            *rows,
            "",
            f"Holds cut short (repeated): {res['cut']}, of which the page lost its kernel: {res['lost']}. "
            f"Total {time.monotonic() - started:.0f} s. "
            "Machine: 2 shared cores, other jobs running; indicative figures.",
        ]
    )
    out = ROOT / "bench" / "results-drive.md"
    out.write_text(text + "\n", encoding="utf-8")
    print(text)
    return 0 if res["stopped"] else 1


if __name__ == "__main__":
    sys.exit(main())
