"""Accessibility-check benchmark: the check alone on the generated 200 x 200 m storey (2500 rooms).

The storey is written as IndoorGML by :func:`bench_convert.generated_gml` with a navigation graph
added (4900 transitions, one per door), read and rasterised once;
then only :func:`pmk_nb.access.check.check_grid` is timed, and run again for its peak memory
(tracemalloc: numpy buffers included; the grid and plan are allocated before tracing starts).

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


def with_graph(path: Path, nx: int, ny: int) -> Path:
    """The generated storey plus its navigation graph (1.0 spelling): one state per room, a transition
    through each of its doors, so the check has every door to test (the file alone has no graph)."""
    states = "".join(
        f'<stateMember><State gml:id="S{i}-{j}"><duality xlink:href="#F0-r{i}-{j}"/></State></stateMember>'
        for i in range(nx)
        for j in range(ny)
    )
    pairs = [((i, j), (i + 1, j)) for i in range(nx - 1) for j in range(ny)]
    pairs += [((i, j), (i, j + 1)) for i in range(nx) for j in range(ny - 1)]
    edges = "".join(
        f'<transitionMember><Transition gml:id="T{k}"><connects xlink:href="#S{a[0]}-{a[1]}"/>'
        f'<connects xlink:href="#S{b[0]}-{b[1]}"/></Transition></transitionMember>'
        for k, (a, b) in enumerate(pairs)
    )
    graph = (
        '<multiLayeredGraph><MultiLayeredGraph gml:id="G"><spaceLayers gml:id="L"><spaceLayerMember>'
        f'<SpaceLayer gml:id="SL"><nodes gml:id="N">{states}</nodes><edges gml:id="E">{edges}</edges>'
        "</SpaceLayer></spaceLayerMember></spaceLayers></MultiLayeredGraph></multiLayeredGraph>"
    )
    text = path.read_text(encoding="utf-8").replace("</IndoorFeatures>", graph + "</IndoorFeatures>")
    path.write_text(text, encoding="utf-8")
    return path


def main(resolutions: list[float]) -> None:
    from bench_convert import generated_gml

    from pmk_nb.access import check_grid
    from pmk_nb.indoorgml import read_building
    from pmk_nb.openings import plan_openings
    from pmk_nb.raster import RasterOptions, rasterise_storey

    with tempfile.TemporaryDirectory() as tmp:
        building = read_building(with_graph(generated_gml(Path(tmp), 1, 50, 50, 4.0, 4.0), 50, 50))
    storey = building.storeys[0].name
    plan = plan_openings(building, storey)
    print("| resolution | cells | check s | check peak MB (tracemalloc) | links passable |")
    print("|---|---|---|---|---|")
    for res in resolutions:
        grid = rasterise_storey(
            building, storey, res, RasterOptions(max_cells=450_000_000, allow_large=True), openings=plan
        )
        t = time.perf_counter()
        report = check_grid(building, storey, grid, plan=plan)
        dt = time.perf_counter() - t  # timed untraced: tracemalloc slows every allocation
        tracemalloc.start()
        check_grid(building, storey, grid, plan=plan)
        peak = tracemalloc.get_traced_memory()[1] / 1e6
        tracemalloc.stop()
        c = report.counts()
        print(
            f"| {res} | {grid.width * grid.height / 1e6:.1f} M | {dt:.2f} | {peak:.0f} | "
            f"{c['passable_chair']}/{c['links']} |",
            flush=True,
        )
        del grid, report


if __name__ == "__main__":
    main([float(a) for a in sys.argv[1:]] or [0.1, 0.05])
