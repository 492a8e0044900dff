"""Chair link benchmark: publish stamp -> link callback latency, delivered rates, client CPU.

A simulated chair runs in its own process (odometry 50 Hz, 1080-ray scans at 40 Hz, chair driving
so messages change). This process runs one ChairLink and records, for every odometry and scan
message, ``time.time()`` at the moment the parsed message is stored minus the message's header
stamp (the sim stamps with ``time.time()`` when it publishes; same host, same clock). That covers
JSON encoding in the sim, the websocket, roslibpy's decoding and our parsing.

Usage: python bench/bench_link.py [--quick] [--seconds S]   -> writes bench/results-link.md
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from sim_process import driving_sim  # noqa: E402 - bench/ is sys.path[0] when run as a script

from pmk_nb.chair.link.client import ChairLink  # noqa: E402
from pmk_nb.chair.messages import parse_scan  # noqa: E402

CASES: list[tuple[str, dict[str, int]]] = [
    ("default throttles (odom 20 ms, scan 50 ms)", {}),
    ("no throttling", {"odom": 0, "scan": 0}),
]


def pct(values: list[float], q: float) -> float:
    return float(np.percentile(values, q)) if values else float("nan")


def run_case(port: int, throttle: dict[str, int], seconds: float) -> dict[str, Any]:
    lat: dict[str, list[float]] = {"odom": [], "scan": []}

    def record(stream: str):  # type: ignore[no-untyped-def]
        def on(msg: Any) -> None:
            if msg.stamp is not None:
                lat[stream].append((time.time() - msg.stamp) * 1000.0)

        return on

    link = ChairLink("127.0.0.1", port, throttle_ms=throttle)
    link.connect(timeout=10.0)
    link.add_listener("odom", record("odom"))
    link.add_listener("scan", record("scan"))
    link.start_streams()
    time.sleep(1.0)  # warm-up
    for v in lat.values():
        v.clear()
    cpu0, t0 = time.process_time(), time.monotonic()
    time.sleep(seconds)
    cpu, wall = time.process_time() - cpu0, time.monotonic() - t0
    counts = {k: len(v) for k, v in lat.items()}
    snapshot = {k: list(v) for k, v in lat.items()}
    link.close()
    return {
        "odom_hz": counts["odom"] / wall,
        "scan_hz": counts["scan"] / wall,
        "odom": (pct(snapshot["odom"], 50), pct(snapshot["odom"], 95), max(snapshot["odom"], default=float("nan"))),
        "scan": (pct(snapshot["scan"], 50), pct(snapshot["scan"], 95), max(snapshot["scan"], default=float("nan"))),
        "cpu": 100.0 * cpu / wall,
    }


def parse_cost_us(rays: int = 1080, repeat: int = 300) -> float:
    rng = np.random.default_rng(0)
    ranges: list[Any] = rng.uniform(0.05, 12.0, rays).tolist()
    ranges[::50] = [None] * len(ranges[::50])
    msg = {
        "header": {"stamp": {"secs": 1, "nsecs": 0}, "frame_id": "laser"},
        "angle_min": -2.35,
        "angle_increment": 4.7 / rays,
        "range_min": 0.1,
        "range_max": 10.0,
        "ranges": ranges,
    }
    t0 = time.perf_counter()
    for _ in range(repeat):
        parse_scan(msg, 0.0)
    return (time.perf_counter() - t0) / repeat * 1e6


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--quick", action="store_true", help="3 s per case")
    args = ap.parse_args()
    seconds = 3.0 if args.quick else args.seconds
    with driving_sim() as (port, _pid):
        results = [(name, run_case(port, throttle, seconds)) for name, throttle in CASES]
    cost = parse_cost_us()
    lines = [
        "## Chair link (`bench/bench_link.py`)",
        "",
        f"Simulated chair in its own process: odometry 50 Hz, 1080-ray LaserScan at 40 Hz, chair driving. "
        f"One ChairLink (roslibpy 2.1, asyncio transport, private loop thread) in this process; {seconds:g} s "
        "per case after 1 s warm-up. Latency = `time.time()` when the parsed message is stored minus the "
        "header stamp the sim wrote with `time.time()` just before encoding (same host, same clock): sim JSON "
        "encoding + websocket + roslibpy decoding + our parsing.",
        "",
        "| case | odom in /s | odom ms p50/p95/max | scans in /s | scan ms p50/p95/max | client CPU % of a core |",
        "|---|---|---|---|---|---|",
    ]
    for name, r in results:
        o, s = r["odom"], r["scan"]
        lines.append(
            f"| {name} | {r['odom_hz']:.1f} | {o[0]:.1f}/{o[1]:.1f}/{o[2]:.1f} | {r['scan_hz']:.1f} | "
            f"{s[0]:.1f}/{s[1]:.1f}/{s[2]:.1f} | {r['cpu']:.0f} |"
        )
    lines += [
        "",
        f"`parse_scan` on a 1080-ray message (with nulls): {cost:.0f} µs per scan (on the I/O thread).",
        "Machine: 2 shared cores, other jobs running; numbers are indicative, not asserts.",
        "",
    ]
    out = ROOT / "bench" / "results-link.md"
    tmp = out.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines))
    tmp.replace(out)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
