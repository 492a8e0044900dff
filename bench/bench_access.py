"""Accessibility-check benchmark: the check alone on the generated 200 x 200 m storey (2500 rooms).

The storey is written as IndoorGML by :func:`bench_convert.generated_gml`, read and rasterised once;
then only :func:`pmk_nb.access.check.check_grid` is timed, its peak memory traced (tracemalloc: numpy
buffers included; the grid and plan are allocated before tracing starts).

Usage: .venv/bin/python bench/bench_access.py [RES ...]   (default 0.1 0.05; PMK_BENCH_CODE=DIR runs
another source tree, as bench_convert does)
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

sys.path.insert(0, os.environ.get("PMK_BENCH_CODE", str(Path(__file__).resolve().parent.parent)))
sys.path.insert(1, str(Path(__file__).resolve().parent))


def main(resolutions: list[float]) -> None:
    from bench_convert import generated_gml

    from pmk_nb.access.check import check_grid
    from pmk_nb.indoorgml import read_building
    from pmk_nb.raster.openings import plan_openings
    from pmk_nb.raster.storey import rasterise_storey

    with tempfile.TemporaryDirectory() as tmp:
        building = read_building(generated_gml(Path(tmp), 1, 50, 50, 4.0, 4.0))
    storey = building.storeys[0].name
    plan = plan_openings(building, storey)
    print("| resolution | cells | check s | check peak MB (tracemalloc) | links passable |")
    print("|---|---|---|---|---|")
    for res in resolutions:
        grid = rasterise_storey(building, storey, res, openings=plan, max_cells=450_000_000, allow_large=True)
        tracemalloc.start()
        t = time.perf_counter()
        report = check_grid(building, storey, grid, plan=plan)
        dt = time.perf_counter() - t
        peak = tracemalloc.get_traced_memory()[1] / 1e6
        tracemalloc.stop()
        c = report.counts()
        print(f"| {res} | {grid.width * grid.height / 1e6:.1f} M | {dt:.2f} | {peak:.0f} | "
              f"{c['passable_chair']}/{c['links']} |", flush=True)
        del grid, report


if __name__ == "__main__":
    main([float(a) for a in sys.argv[1:]] or [0.1, 0.05])
