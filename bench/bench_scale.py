"""Converter scaling (issue 31): whole `pmk convert` processes, as a user runs them, beside the goals.

Three tables, each row a fresh process (interpreter start and imports included):

* **scaling**: a generated storey at 1x, 2x, 4x and 8x the plan (rooms, door cells, door lines,
  transitions and area all grow together) at 0.1 m: time and peak memory, ratio to 1x. Goal: no step
  quadratic, n x the plan in at most 1.2 n x the time (4x <= 4.8x).
* **small plans**: the sample maps (sample_maps/*.gml) at 0.05 m, run as `python -m pmk_nb.cli convert`.
  Goal: a plan writing < 1 MB converts in <= 0.5 s and <= 150 MB.
* **100 M cells**: the 4x storey at the resolution that makes about 100 M cells. Goals (issue 37, which
  replaced issue 31's "3 x writing", a goal below its own floor): the process in <= 3 x its floor, the
  floor being a fresh process that only imports what the convert run imported (:func:`floor`) plus
  that run's own reading and writing (the map_server set: PGM, preview PNG and YAML, encoded, written
  and fsynced; moving the staged set into place); peak memory <= 3 x (grid + input file).

Time is given twice: wall (what the user waits) and CPU (user + system of the process, which other jobs
on a shared machine disturb far less); goals are judged on both. Peak = the process's maximum RSS.
Every row runs REPEAT (3) times: wall and its write time from the run of least wall, CPU and its write
CPU from the run of least CPU, peak the least.

Generated storey (IndoorGML 1.0, State/Transition graph): nx x ny rooms 3.8 m square on a 4 m pitch (the
walls are 0.2 m gaps the file leaves out), a door cell (navi:ConnectionSpace) filling each vertical
wall gap and a door line (navi:ConnectionBoundary) in each horizontal one, every door joined by
transitions: 1x = 16 x 16 rooms (256 rooms, 240 door cells, 720 transitions, 64 m x 64 m).

Usage: .venv/bin/python bench/bench_scale.py [--quick]   -> writes bench/results-scale.md
(``--quick``: no 8x row and no 100 M-cell row.)
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
SAMPLE_MAPS = ROOT / "sample_maps"
RES = 0.1
SCALES = ((1, 16, 16), (2, 32, 16), (4, 32, 32), (8, 64, 32))  # (factor, nx, ny)
SLACK = 1.2  # n x the plan may take 1.2 n x the time
SMALL_S, SMALL_MB, SMALL_OUT_MB = 0.5, 150.0, 1.0
FLOOR_RATIO, MEMORY_RATIO, BIG_CELLS = 3.0, 3.0, 100e6
REPEAT = 3  # every row runs this many times; the least wall and the least CPU are shown (a shared machine
# only ever adds time to a run, so the least is the closest to the machine's own figure)

NS = (
    'xmlns="http://www.opengis.net/indoorgml/1.0/core" xmlns:gml="http://www.opengis.net/gml/3.2" '
    'xmlns:xlink="http://www.w3.org/1999/xlink" xmlns:navi="http://www.opengis.net/indoorgml/1.0/navigation"'
)


def _cell(cid: str, x0: float, y0: float, x1: float, y1: float, tag: str = "CellSpace") -> str:
    ring = f"{x0:g} {y0:g} {x1:g} {y0:g} {x1:g} {y1:g} {x0:g} {y1:g} {x0:g} {y0:g}"
    return (
        f'<cellSpaceMember><{tag} gml:id="{cid}"><cellSpaceGeometry><Geometry2D><gml:Polygon><gml:exterior>'
        f"<gml:LinearRing><gml:posList>{ring}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon>"
        f"</Geometry2D></cellSpaceGeometry></{tag}></cellSpaceMember>\n"
    )


def _door_line(bid: str, x0: float, y: float, x1: float) -> str:
    return (
        f'<cellSpaceBoundaryMember><navi:ConnectionBoundary gml:id="{bid}"><cellSpaceBoundaryGeometry>'
        f"<geometry2D><gml:LineString><gml:posList>{x0:g} {y:g} {x1:g} {y:g}</gml:posList></gml:LineString>"
        f"</geometry2D></cellSpaceBoundaryGeometry></navi:ConnectionBoundary></cellSpaceBoundaryMember>\n"
    )


def storey_gml(folder: Path, nx: int, ny: int) -> tuple[Path, dict[str, int]]:
    """The generated storey of nx x ny rooms (see the module docstring) and its counts."""
    cells, lines, pairs = [], [], []
    for i in range(nx):
        for j in range(ny):
            x, y, room = i * 4.0, j * 4.0, f"R{i}_{j}"
            cells.append(_cell(room, x, y, x + 3.8, y + 3.8))
            if i + 1 < nx:
                door = f"D{i}_{j}"
                cells.append(_cell(door, x + 3.8, y + 1.45, x + 4.0, y + 2.35, "navi:ConnectionSpace"))
                pairs += [(room, door), (door, f"R{i + 1}_{j}")]
            if j + 1 < ny:
                lines.append(_door_line(f"B{i}_{j}", x + 1.45, y + 3.9, x + 2.35))
                pairs.append((room, f"R{i}_{j + 1}"))
    states = "".join(
        f'<stateMember><State gml:id="S{c}"><duality xlink:href="#{c}"/></State></stateMember>\n'
        for c in sorted({c for p in pairs for c in p})
    )
    edges = "".join(
        f'<transitionMember><Transition gml:id="T{k}"><connects xlink:href="#S{a}"/><connects xlink:href="#S{b}"/>'
        f"</Transition></transitionMember>\n"
        for k, (a, b) in enumerate(pairs)
    )
    path = folder / f"storey_{nx}x{ny}.gml"
    path.write_text(
        f'<?xml version="1.0"?>\n<IndoorFeatures {NS} gml:id="F"><primalSpaceFeatures><PrimalSpaceFeatures gml:id="P">'
        f"{''.join(cells)}{''.join(lines)}</PrimalSpaceFeatures></primalSpaceFeatures><multiLayeredGraph>"
        f'<MultiLayeredGraph gml:id="G"><spaceLayers gml:id="L"><spaceLayerMember><SpaceLayer gml:id="SL">'
        f'<nodes gml:id="N">{states}</nodes><edges gml:id="E">{edges}</edges></SpaceLayer></spaceLayerMember>'
        f"</spaceLayers></MultiLayeredGraph></multiLayeredGraph></IndoorFeatures>\n",
        encoding="utf-8",
    )
    counts = {"rooms": nx * ny, "door cells": (nx - 1) * ny, "transitions": len(pairs)}
    return path, counts


# --- the measured process -------------------------------------------------------------------------


def child(report: str, argv: list[str]) -> int:
    """`pmk convert ARGV` in this process, with the time spent writing files recorded in ``report``:
    the map set (:func:`pmk_nb.rosmap.files.write_map`: PGM, preview PNG, YAML, each fsynced) and moving
    the staged sets into place (``replace_all``); also the time reading the plan, and the modules the
    run imported (for :func:`floor`)."""
    before = set(sys.modules)
    import pmk_nb.indoorgml as indoorgml
    import pmk_nb.library.convert as convert
    import pmk_nb.rosmap as rosmap
    import pmk_nb.rosmap.files as files
    from pmk_nb.cli import main

    spent = {"write_s": 0.0, "write_cpu": 0.0, "read_s": 0.0, "read_cpu": 0.0, "cells": 0}

    def timed(fn: Any, what: str, grid_arg: bool = False) -> Any:
        """``fn``, its wall and CPU time added to spent[what + "_s"] and spent[what + "_cpu"]."""

        def run(*args: Any, **kw: Any) -> Any:
            w, c = time.perf_counter(), time.process_time()
            try:
                return fn(*args, **kw)
            finally:
                spent[f"{what}_s"] += time.perf_counter() - w
                spent[f"{what}_cpu"] += time.process_time() - c
                if grid_arg:
                    spent["cells"] += args[0].width * args[0].height

        return run

    # both names: the rosmap face keeps the function once a name is first taken from it
    files.write_map = rosmap.write_map = timed(files.write_map, "write", grid_arg=True)
    convert.replace_all = timed(convert.replace_all, "write")
    # convert_plan takes it from the package face at call time
    indoorgml.read_building = timed(indoorgml.read_building, "read")
    code = main(["convert", *argv])
    modules = [m for m in sys.modules if m not in before]
    Path(report).write_text(json.dumps({**spent, "modules": modules}), encoding="utf-8")
    return code


def floor_child(modules_json: str) -> int:
    """Import every module a convert run imported (in its order), and nothing else: the start-up a
    convert process pays before it reads a byte (:func:`floor`)."""
    for name in json.loads(Path(modules_json).read_text(encoding="utf-8")):
        try:
            importlib.import_module(name)
        except Exception:  # a module that only imports as part of another, or __main__
            pass
    return 0


# compiled modules are kept here for the whole run, as an installed package has them (a checkout run with
# PYTHONDONTWRITEBYTECODE would compile every module in every process: +0.1 s)
PYCACHE = tempfile.TemporaryDirectory(prefix="bench-scale-pycache-")


def run(argv: list[str], wrapped: bool) -> dict[str, Any]:
    """One `pmk convert` process: wall and CPU seconds, peak RSS (MB), output MB (and writing time)."""
    with tempfile.TemporaryDirectory(prefix="bench-scale-") as tmp:
        out, report = Path(tmp) / "out", Path(tmp) / "report.json"
        args = [*argv, "--out", str(out), "--no-progress"]
        cmd = (
            [sys.executable, __file__, "--child", str(report), *args]
            if wrapped
            else [sys.executable, "-m", "pmk_nb.cli", "convert", *args]
        )
        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        # the environment a user has: numpy's BLAS threads start as they do for them (about 0.08 s of CPU
        # per process on 2 cores, no wall time); OPENBLAS_NUM_THREADS=1 here hid that from the CPU rows
        env.update(PYTHONPATH=str(ROOT), PYTHONPYCACHEPREFIX=PYCACHE.name)
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, cwd=ROOT)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        err = proc.stderr.read().decode(errors="replace") if proc.stderr else ""
        proc.returncode = os.waitstatus_to_exitcode(status)
        if proc.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed ({proc.returncode}): {err.strip()[-300:]}")
        r = {
            "wall": wall,
            "cpu": usage.ru_utime + usage.ru_stime,
            "peak_mb": usage.ru_maxrss / 1024,
            "out_mb": sum(p.stat().st_size for p in out.iterdir()) / 1e6,
        }
        if wrapped:
            r.update(json.loads(report.read_text(encoding="utf-8")))
    return r


def best(argv: list[str], wrapped: bool, repeat: int = REPEAT) -> dict[str, Any]:
    """:func:`run` ``repeat`` times: wall (and the write time) of the run of least wall, CPU (and the write
    CPU) of the run of least CPU, the least peak; a ratio is always taken within one run."""
    runs = [run(argv, wrapped) for _ in range(repeat)]
    fast, lean = min(runs, key=lambda r: r["wall"]), min(runs, key=lambda r: r["cpu"])
    out = dict(lean)
    out.update(wall=fast["wall"], peak_mb=min(r["peak_mb"] for r in runs), runs=repeat)
    if wrapped:
        out.update(write_s=fast["write_s"], read_s=fast["read_s"])
    return out


def floor(modules: list[str], folder: Path) -> dict[str, float]:
    """A process that starts and imports what a convert run imported, and stops (least wall and least
    CPU of REPEAT): with that run's own reading and writing, the floor under its time (see big_storey)."""
    listing = folder / "modules.json"
    listing.write_text(json.dumps(modules), encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env.update(PYTHONPATH=str(ROOT), PYTHONPYCACHEPREFIX=PYCACHE.name)
    walls, cpus = [], []
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        proc = subprocess.Popen([sys.executable, __file__, "--floor", str(listing)], env=env, cwd=ROOT)
        _, status, usage = os.wait4(proc.pid, 0)
        walls.append(time.perf_counter() - t0)
        cpus.append(usage.ru_utime + usage.ru_stime)
        if os.waitstatus_to_exitcode(status) != 0:
            raise RuntimeError("the start-up floor process failed")
    return {"wall": min(walls), "cpu": min(cpus)}


# --- tables ---------------------------------------------------------------------------------------


def _verdict(ok: bool) -> str:
    return "met" if ok else "**not met**"


GOALS: list[str] = []  # one summary row per goal, filled by the tables below: goal | measured | verdict


def _goal(goal: str, measured: str, *ok: bool) -> None:
    """One summary row; ``ok``: the verdict on each measure named in ``goal`` (wall; CPU), or one verdict."""
    GOALS.append(f"| {goal} | {measured} | {'; '.join(_verdict(x) for x in ok)} |")


def _load() -> str:
    one, five, fifteen = os.getloadavg()
    return f"{one:.1f} / {five:.1f} / {fifteen:.1f}"


def scaling(folder: Path, quick: bool) -> list[str]:
    rows, base = [], None
    for factor, nx, ny in SCALES[:3] if quick else SCALES:
        path, n = storey_gml(folder, nx, ny)
        r = best([str(path), "-r", str(RES)], wrapped=True)
        base = base or r
        r.update(n, factor=factor, wall_x=r["wall"] / base["wall"], cpu_x=r["cpu"] / base["cpu"])
        rows.append(r)
        print(f"scale {factor}x: {r['wall']:.2f} s wall, {r['cpu']:.2f} s CPU", file=sys.stderr, flush=True)
    lines = [
        "### Scaling: n x the plan, whole `pmk convert` process",
        "",
        f"Generated storey at {RES} m (1x = 16 x 16 rooms; see bench_scale.py); ratio = time / time of 1x "
        f"(goal <= {SLACK:g} n; the fixed start-up of about 0.4 s is part of every row); least of {REPEAT} runs.",
        "",
        "| plan | rooms | door cells | transitions | cells | wall s | CPU s | wall / 1x | CPU / 1x | peak MB "
        "| goal: / 1x <= | wall / CPU |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in rows:
        limit = SLACK * r["factor"]
        goal = "-" if r["factor"] == 1 else f"{_verdict(r['wall_x'] <= limit)} / {_verdict(r['cpu_x'] <= limit)}"
        lines.append(
            f"| {r['factor']}x | {r['rooms']} | {r['door cells']} | {r['transitions']} | {r['cells'] / 1e6:.2f} M "
            f"| {r['wall']:.2f} | {r['cpu']:.2f} | {r['wall_x']:.2f} | {r['cpu_x']:.2f} | {r['peak_mb']:.0f} "
            f"| {'-' if r['factor'] == 1 else f'{limit:g}'} | {goal} |"
        )
        if r["factor"] > 1:
            _goal(
                f"{r['factor']}x the plan in <= {limit:g}x the time of 1x (wall; CPU)",
                f"{r['wall_x']:.2f}x; {r['cpu_x']:.2f}x",
                r["wall_x"] <= limit,
                r["cpu_x"] <= limit,
            )
    return lines


def small_plans() -> list[str]:
    lines = [
        "",
        f"### Small plans: `python -m pmk_nb.cli convert FILE -r 0.05`, fresh process (least of {REPEAT})",
        "",
        f"Goal for a plan writing < {SMALL_OUT_MB:g} MB: <= {SMALL_S} s and <= {SMALL_MB:g} MB peak, imports "
        "included (modules compiled once beforehand, as installed).",
        "",
        "| plan | output MB | wall s | CPU s | peak MB | goal (wall / CPU) |",
        "|---|---:|---:|---:|---:|---|",
    ]
    for path in sorted(SAMPLE_MAPS.glob("*.gml")):
        r = best([str(path), "-r", "0.05"], wrapped=False)
        small = r["out_mb"] < SMALL_OUT_MB
        goal = (
            "- (writes more)"
            if not small
            else (
                f"{_verdict(r['wall'] <= SMALL_S and r['peak_mb'] <= SMALL_MB)} / "
                f"{_verdict(r['cpu'] <= SMALL_S and r['peak_mb'] <= SMALL_MB)}"
            )
        )
        lines.append(
            f"| {path.name} | {r['out_mb']:.2f} | {r['wall']:.2f} | {r['cpu']:.2f} | {r['peak_mb']:.0f} | {goal} |"
        )
        if small:
            _goal(
                f"{path.name} (< {SMALL_OUT_MB:g} MB out): <= {SMALL_S} s (wall; CPU), <= {SMALL_MB:g} MB peak",
                f"{r['wall']:.2f} s; {r['cpu']:.2f} s; {r['peak_mb']:.0f} MB",
                r["wall"] <= SMALL_S,
                r["cpu"] <= SMALL_S,
                r["peak_mb"] <= SMALL_MB,
            )
        print(f"small {path.name}: {r['wall']:.2f} s wall", file=sys.stderr, flush=True)
    return lines


def big_storey(folder: Path) -> list[str]:
    nx, ny = 32, 32
    path, n = storey_gml(folder, nx, ny)
    res = round(((nx * 4.0) * (ny * 4.0) / BIG_CELLS) ** 0.5, 5)
    r = best([str(path), "-r", str(res)], wrapped=True)
    held_mb = r["cells"] / 1e6 + path.stat().st_size / 1e6  # one byte per cell
    start = floor(r["modules"], folder)
    # the least any convert of this plan can take: start, imports, reading the file, writing the files
    low_wall = start["wall"] + r["read_s"] + r["write_s"]
    low_cpu = start["cpu"] + r["read_cpu"] + r["write_cpu"]
    print(f"100 M cells: {r['wall']:.2f} s wall, write {r['write_s']:.2f} s", file=sys.stderr, flush=True)
    wall_x, cpu_x, mem_x = r["wall"] / r["write_s"], r["cpu"] / max(r["write_cpu"], 1e-9), r["peak_mb"] / held_mb
    floor_wall, floor_cpu = r["wall"] / low_wall, r["cpu"] / max(low_cpu, 1e-9)
    _goal(
        f"100 M cells: process <= {FLOOR_RATIO:g} x its floor: start + imports + reading + writing (wall; CPU)",
        f"{floor_wall:.1f}x; {floor_cpu:.1f}x",
        floor_wall <= FLOOR_RATIO,
        floor_cpu <= FLOOR_RATIO,
    )
    _goal(
        f"above 10 M cells: peak <= {MEMORY_RATIO:g} x (grid + input)",
        f"{r['peak_mb']:.0f} MB = {mem_x:.2f}x",
        mem_x <= MEMORY_RATIO,
    )
    return [
        "",
        f"### 100 M cells: the 4x storey ({n['rooms']} rooms, {n['transitions']} transitions) at {res} m",
        "",
        "write = time in writing the files (PGM, preview PNG, YAML: encode, disk, fsync; moving the staged set "
        f"into place), measured inside the process; least of {REPEAT} runs, each ratio within one run; goals: "
        f"process / floor <= {FLOOR_RATIO:g} (the floor: below), peak <= "
        f"{MEMORY_RATIO:g} x (grid + input).",
        "",
        "| cells | input MB | output MB | wall s | write s | wall / write | CPU s | write CPU s | CPU / write CPU "
        "| peak MB | peak / (grid + input) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        f"| {r['cells'] / 1e6:.0f} M | {path.stat().st_size / 1e6:.1f} | {r['out_mb']:.0f} | {r['wall']:.2f} | "
        f"{r['write_s']:.2f} | {wall_x:.1f} | {r['cpu']:.2f} | {r['write_cpu']:.2f} | {cpu_x:.1f} | "
        f"{r['peak_mb']:.0f} | {mem_x:.2f} |",
        "",
        f"- process / floor <= {FLOOR_RATIO:g}: wall {floor_wall:.1f}x {_verdict(floor_wall <= FLOOR_RATIO)}, "
        f"CPU {floor_cpu:.1f}x {_verdict(floor_cpu <= FLOOR_RATIO)}",
        f"- peak <= {MEMORY_RATIO:g} x (grid + input): {_verdict(mem_x <= MEMORY_RATIO)}",
        "",
        "The floor under this goal: what the same process spends before and around the conversion itself. "
        "start = a fresh process importing every module the convert run imported, and nothing else; read = "
        "the convert run's own reading of the file (parse, geometry, graph); write = as above. What is left "
        "is the conversion: openings, rasterising, the accessibility check, the witness (the written files "
        "read back and judged against the plan), the rooms file.",
        "",
        "| | start + imports s | read s | write s | floor s | floor / write | conversion s | process / write |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
        f"| wall | {start['wall']:.2f} | {r['read_s']:.2f} | {r['write_s']:.2f} | {low_wall:.2f} | "
        f"{low_wall / r['write_s']:.1f} | {r['wall'] - low_wall:.2f} | {wall_x:.1f} |",
        f"| CPU | {start['cpu']:.2f} | {r['read_cpu']:.2f} | {r['write_cpu']:.2f} | {low_cpu:.2f} | "
        f"{low_cpu / max(r['write_cpu'], 1e-9):.1f} | {r['cpu'] - low_cpu:.2f} | {cpu_x:.1f} |",
        "",
        f"- the floor is {low_wall / r['write_s']:.1f}x (wall) and {low_cpu / max(r['write_cpu'], 1e-9):.1f}x "
        f"(CPU) the time of writing its files; the goal of {FLOOR_RATIO:g}x the floor leaves the conversion "
        f"{(FLOOR_RATIO - 1) * low_wall:.2f} s of wall and {(FLOOR_RATIO - 1) * low_cpu:.2f} s of CPU for 100 M cells",
    ]


def main() -> int:
    if len(sys.argv) >= 3 and sys.argv[1] == "--child":
        sys.path.insert(0, str(ROOT))
        return child(sys.argv[2], sys.argv[3:])
    if len(sys.argv) == 3 and sys.argv[1] == "--floor":
        sys.path.insert(0, str(ROOT))
        return floor_child(sys.argv[2])
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="no 8x row, no 100 M-cell row")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results-scale.md")
    args = ap.parse_args()
    started, load0 = time.perf_counter(), _load()
    with tempfile.TemporaryDirectory(prefix="bench-scale-plans-") as tmp:
        lines = [
            "## Convert scaling and whole-process goals (issue 31)",
            "",
            f"`bench/bench_scale.py`"
            f"{' --quick' if args.quick else ''}: each row a fresh process, interpreter start and imports "
            "included. Time twice: wall (what the user waits) and CPU (user + system of the process, which "
            "other jobs on a shared machine disturb far less); goals judged on both. Peak = the process's "
            "maximum RSS.",
            "",
        ]
        for path in sorted(SAMPLE_MAPS.glob("*.gml")):  # not measured: compiles the modules once
            run([str(path), "-r", "0.05"], wrapped=True)
        lines += scaling(Path(tmp), args.quick) + small_plans()
        if not args.quick:
            lines += big_storey(Path(tmp))
    head = [
        "### Goals (issue 31): goal, measured, verdict per measure",
        "",
        "| goal | measured | verdict |",
        "|---|---|---|",
    ]
    load = f"Load average (1 / 5 / 15 min) at the start: {load0}; at the end: {_load()} (wall times carry it)."
    lines[4:4] = [*head, *GOALS, "", load, ""]
    lines += ["", f"Total benchmark time {time.perf_counter() - started:.0f} s.", ""]
    args.out.write_text("\n".join(lines), encoding="utf-8")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
