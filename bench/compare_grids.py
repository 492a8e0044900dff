"""What a change to the converter does to real plans: two source trees, the same files, side by side.

Each tree converts each plan (``pmk convert``, default 0.05 m) and checks it (``pmk check --json``) in
its own child process, so the two versions never share an import. Printed as Markdown: per storey,
how many cells went FREE <-> OCCUPIED <-> UNKNOWN; per plan, the check's exit code and verdict;
and every link whose rule, planned width, free width or chair verdict changed. Nothing is written
into either tree.

Usage: python bench/compare_grids.py OLD_TREE NEW_TREE [--resolution 0.05] [FILE.gml ...]
(default files: /work/shared/data/indoorgml/*.gml)
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # only to read the written maps back (read the same by every version)
SHARED = Path("/work/shared/data/indoorgml")
VALUES = {0: "F", 100: "O", -1: "U"}
MOVES = [(0, 100), (0, -1), (100, 0), (100, -1), (-1, 0), (-1, 100)]


def _run(tree: Path, plan: Path, out: Path, resolution: float) -> dict[str, Any]:
    """Convert and check ``plan`` with the code in ``tree``: grids by storey, links, verdict."""
    py = [sys.executable, "-m", "pmk_nb.cli"]
    env = {**os.environ, "PYTHONPATH": str(tree)}
    conv = [*py, "convert", "-r", str(resolution), "--out", str(out), "--name", "m", "--no-preview", str(plan)]
    subprocess.run(conv, cwd=tree, env=env, capture_output=True, text=True, check=False)
    check = subprocess.run(
        [*py, "check", "-r", str(resolution), "--json", str(plan)],
        cwd=tree,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    from pmk_nb.rosmap import read_map

    grids = {y.stem: np.asarray(read_map(y).data) for y in sorted(out.glob("m*.yaml"))}
    try:
        report = json.loads(check.stdout)
    except json.JSONDecodeError:
        report = {}
    links = {
        k["link"]: (k["rule"], k["width"], k.get("free_width"), k["chair"])
        for s in report.get("storeys", [])
        for k in s.get("links", [])
    }
    return {"grids": grids, "links": links, "rc": check.returncode, "ok": report.get("ok")}


def _grid_rows(name: str, old: dict[str, Any], new: dict[str, Any]) -> list[str]:
    rows = []
    for storey, a in old["grids"].items():
        b = new["grids"].get(storey)
        if b is None or a.shape != b.shape:
            rows.append(f"| {name} {storey} | {a.size} | shape {a.shape} -> {None if b is None else b.shape} |")
            continue
        moved = [int(((a == x) & (b == y)).sum()) for x, y in MOVES]
        rows.append(f"| {name} {storey} | {a.size} | " + " | ".join(map(str, moved)) + " |")
    return rows


def _link_rows(name: str, old: dict[str, Any], new: dict[str, Any]) -> list[str]:
    return [
        f"- {name} {link}: (rule, width, free width, chair) {old['links'][link]} -> {new['links'].get(link)}"
        for link in sorted(old["links"])
        if old["links"][link] != new["links"].get(link)
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("files", nargs="*", type=Path)
    ap.add_argument("--resolution", type=float, default=0.05)
    args = ap.parse_args()
    files = args.files or sorted(SHARED.glob("*.gml"))
    grid_rows, verdicts, links = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for plan in files:
            old = _run(args.old.resolve(), plan, Path(tmp, "old", plan.stem), args.resolution)
            new = _run(args.new.resolve(), plan, Path(tmp, "new", plan.stem), args.resolution)
            grid_rows += _grid_rows(plan.stem, old, new)
            verdicts.append(f"- {plan.stem}: check exit {old['rc']} -> {new['rc']} (ok {old['ok']} -> {new['ok']})")
            links += _link_rows(plan.stem, old, new)
    head = " | ".join(f"{VALUES[x]}->{VALUES[y]}" for x, y in MOVES)
    print(f"| plan storey | cells | {head} |\n|---|---|" + "---|" * len(MOVES))
    print("\n".join(grid_rows), "", *verdicts, "", *(links or ["- no link changed"]), sep="\n")


if __name__ == "__main__":
    main()
