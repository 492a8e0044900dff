"""`pmk bench`: run the benchmark scripts in the checkout's bench/ folder and merge their tables.

Each script `bench/bench_<area>.py` writes `bench/results-<area>.md`; this command runs the chosen
ones (each in its own process, so peak-memory figures do not mix) and concatenates every
`results-*.md` into `bench/results.md` with the machine it ran on.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import os
import platform
import subprocess
import sys
from pathlib import Path

from pmk_nb.cli.options import Subparsers
from pmk_nb.errors import PmkError
from pmk_nb.fileio import atomic_write

AREAS = ("convert", "scale", "deploy", "sim", "link", "live", "drive")


def bench_dir() -> Path:
    here = Path(__file__).resolve().parents[2] / "bench"
    if not here.is_dir():
        raise PmkError(f"no bench/ folder next to the package ({here}); run `pmk bench` from a source checkout")
    return here


def add_parser(sub: Subparsers) -> None:
    p = sub.add_parser("bench", help="run benchmarks and write bench/results.md")
    p.add_argument("areas", nargs="*", default=["all"], help=f"all or some of: {', '.join(AREAS)}")
    p.add_argument("--quick", action="store_true", help="smaller cases, for a smoke run")
    p.set_defaults(run=run)


def merge_results(folder: Path) -> Path:
    parts = sorted(folder.glob("results-*.md"))
    cpu = platform.processor() or platform.machine()
    head = [
        "# PMK Notebook benchmark results",
        "",
        f"Merged {_dt.datetime.now(_dt.UTC):%Y-%m-%d %H:%M} UTC on {platform.node()} "
        f"({os.cpu_count()} cores, {cpu}, Python {platform.python_version()}).",
        "Each section comes from `bench/bench_<area>.py` (run: `make bench` or `pmk bench AREA`).",
        "",
    ]
    body = [p.read_text(encoding="utf-8").rstrip() + "\n" for p in parts]
    out = folder / "results.md"
    try:
        atomic_write(out, "\n".join(head) + "\n" + "\n".join(body))
    except OSError as err:
        raise PmkError(f"cannot write {out}: {err.strerror or err}") from err
    return out


def run(args: argparse.Namespace) -> int:
    folder = bench_dir()
    areas = list(AREAS) if "all" in args.areas else args.areas
    unknown = [a for a in areas if a not in AREAS]
    if unknown:
        raise PmkError(f"unknown benchmark {', '.join(unknown)}; choose from {', '.join(AREAS)}")
    failed = []
    for area in areas:
        script = folder / f"bench_{area}.py"
        if not script.exists():
            print(f"bench {area}: {script.name} missing, skipped", file=sys.stderr)
            failed.append(area)
            continue
        print(f"== bench {area}", flush=True)
        cmd = [sys.executable, str(script)] + (["--quick"] if args.quick else [])
        if subprocess.run(cmd, check=False).returncode != 0:
            failed.append(area)
    out = merge_results(folder)
    print(f"wrote {out}")
    if failed:
        print(f"benchmarks that failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0
