"""Classroom pages, measured: CPU and memory of one page's kernel + its own chair (issue 26).

``pmk demo --classroom``'s world served by Voilà; ``--pages`` headless Chromium pages stay on Home
with the live view running, each page's kernel running its own simulated chair (the classroom rates of
:mod:`pmk_nb.classroom.settings`).  After a warm-up, for ``--seconds``, psutil samples each
kernel (chair included: it is a thread of the kernel), Voilà's server and Chromium (all its
processes, divided by the pages).  Writes ``bench/results-classroom.md``.

Usage: python bench/classroom_pages.py [--pages N] [--seconds S]     (not part of ``make test``)
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT)]

import psutil  # noqa: E402

from pmk_nb.classroom.settings import ODOM_RATE, RAYS, SCAN_RATE  # noqa: E402
from pmk_nb.cli.demo_classroom import prepare_classroom  # noqa: E402
from pmk_nb.serve.procs import free_port, stop_process, wait_for_port  # noqa: E402
from pmk_nb.serve.voila import voila_command, write_dashboard_notebook  # noqa: E402
from pmk_nb.ui import KIOSK_ENV  # noqa: E402
from tests.browser.kiosk_page import CHROMIUM, CHROMIUM_ARGS, VIEWPORT  # noqa: E402

MIB = 1024 * 1024


def _tree_cpu_rss(procs: list[psutil.Process]) -> tuple[float, float]:
    cpu = rss = 0.0
    for p in procs:
        try:
            cpu += p.cpu_percent(None)
            rss += p.memory_info().rss
        except psutil.Error:
            pass
    return cpu, rss / MIB


def measure(pages: int, seconds: float, warmup: float) -> dict[str, object]:
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory(prefix="pmk-classroom-bench-") as tmp:
        room = prepare_classroom(Path(tmp) / "demo", max_chairs=max(pages, 1))
        room.env[KIOSK_ENV] = "0"
        port = free_port()
        notebook = write_dashboard_notebook(Path(tmp) / "served")
        voila = subprocess.Popen(
            voila_command(notebook, port=port),
            env=room.env,
            cwd=notebook.parent,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        try:
            wait_for_port("127.0.0.1", port, voila, "Voilà", 120.0)
            with sync_playwright() as pw:
                browser = pw.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True)
                for _ in range(pages):
                    page = browser.new_page(viewport=VIEWPORT)
                    page.set_default_timeout(180_000)
                    page.goto(f"http://127.0.0.1:{port}/", wait_until="domcontentloaded")
                    page.wait_for_selector(".pmk-home-info-state:has-text('Live')", timeout=180_000)
                time.sleep(warmup)
                chairs = json.loads((Path(room.settings.state_dir) / "chairs.json").read_text())
                kernels = [psutil.Process(int(pid)) for pid in chairs]
                server = [psutil.Process(voila.pid)]
                ours = psutil.Process().children(recursive=True)  # not another run's Chromium on a shared machine
                chromium = [p for p in ours if "chrom" in p.name().lower()]
                groups = {"kernel": kernels, "server": server, "chromium": chromium}
                for procs in groups.values():
                    _tree_cpu_rss(procs)  # prime cpu_percent
                samples: dict[str, list[tuple[float, float]]] = {k: [] for k in groups}
                per_kernel: list[list[tuple[float, float]]] = [[] for _ in kernels]
                end = time.monotonic() + seconds
                while time.monotonic() < end:
                    time.sleep(2.0)
                    for name, procs in groups.items():
                        samples[name].append(_tree_cpu_rss(procs))
                    for i, k in enumerate(kernels):
                        per_kernel[i].append(_tree_cpu_rss([k]))
                browser.close()
        finally:
            stop_process(voila)
    cpu = [statistics.mean(c for c, _ in s) for s in per_kernel]
    rss = [max(r for _, r in s) for s in per_kernel]
    return {
        "pages": pages,
        "seconds": seconds,
        "cores": psutil.cpu_count(),
        "kernel_cpu_percent_mean": statistics.mean(cpu),
        "kernel_cpu_percent_max": max(cpu),
        "kernel_rss_mib_mean": statistics.mean(rss),
        "kernel_rss_mib_max": max(rss),
        "server_cpu_percent": statistics.mean(c for c, _ in samples["server"]),
        "server_rss_mib": max(r for _, r in samples["server"]),
        "chromium_cpu_percent_per_page": statistics.mean(c for c, _ in samples["chromium"]) / pages,
        "chromium_rss_mib_per_page": max(r for _, r in samples["chromium"]) / pages,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pages", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--warmup", type=float, default=10.0)
    args = parser.parse_args()
    r = measure(args.pages, args.seconds, args.warmup)
    lines = [
        "# Classroom pages: CPU and memory per page (issue 26)",
        "",
        f"`python bench/classroom_pages.py --pages {r['pages']} --seconds {r['seconds']:g}` on {r['cores']} cores; "
        "live view on Home, default page rates, classroom chair rates (odometry "
        f"{ODOM_RATE:g} Hz, laser {SCAN_RATE:g} Hz, {RAYS} rays). "
        "CPU in % of one core (psutil), memory RSS.",
        "",
        "| per page | CPU % (mean) | CPU % (max kernel) | RSS MiB (mean) | RSS MiB (max) |",
        "|---|---|---|---|---|",
        f"| kernel + its chair | {r['kernel_cpu_percent_mean']:.1f} | {r['kernel_cpu_percent_max']:.1f} | "
        f"{r['kernel_rss_mib_mean']:.0f} | {r['kernel_rss_mib_max']:.0f} |",
        f"| browser (Chromium / pages) | {r['chromium_cpu_percent_per_page']:.1f} | | "
        f"{r['chromium_rss_mib_per_page']:.0f} | |",
        f"| Voilà server (all pages) | {r['server_cpu_percent']:.1f} | | {r['server_rss_mib']:.0f} | |",
        "",
    ]
    (HERE / "results-classroom.md").write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
