"""Deploy benchmark: time to send a map and see it live (upload + detect + reload + confirmed).

Two SFTP servers: the simulator's own endpoint (asyncssh) and a real OpenSSH sshd (when this runs
as root with openssh-server installed), both with the simulator's map server reloading the file.
Writes bench/results-deploy.md. Run: `.venv/bin/python bench/bench_deploy.py [--quick]`.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import shutil
import statistics
import sys
import tempfile
import time
import uuid
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from pmk_nb.chair.deploy import STEPS, deploy  # noqa: E402
from pmk_nb.chair.link.client import ChairLink  # noqa: E402
from pmk_nb.chair.profiles import ChairProfile  # noqa: E402
from pmk_nb.grid import OccupancyGrid  # noqa: E402
from pmk_nb.rosmap.files import write_map  # noqa: E402
from pmk_nb.sim import SimChair  # noqa: E402


def building_grid(size: int, seed: int) -> OccupancyGrid:
    """A floor plan-ish grid: outer walls, a corridor grid of inner walls with doors, unknown margin."""
    rng = np.random.default_rng(seed)
    data = np.full((size, size), -1, dtype=np.int8)
    m = size // 20
    data[m:-m, m:-m] = 0
    data[m, m:-m] = data[-m - 1, m:-m] = data[m:-m, m] = data[m:-m, -m - 1] = 100
    step = max(size // 8, 20)
    for k in range(m + step, size - m - 1, step):
        data[m:-m, k] = 100
        data[k, m:-m] = 100
        for d in rng.integers(m + 5, size - m - 15, size=4):
            data[d : d + 10, k] = 0  # doors
            data[k, d : d + 10] = 0
    return OccupancyGrid(data=data, resolution=0.05, origin=(-1.0 - seed * 0.01, -2.0, 0.0))


def run_case(
    sim: SimChair, link: ChairLink, profile: ChairProfile, password: str | None, size: int, repeats: int, work: Path
) -> dict[str, Any]:
    runs: list[dict[str, float]] = []
    image_bytes = 0
    for i in range(repeats):
        files = write_map(building_grid(size, seed=i + 1), work / f"v{i}", f"bench{size}", preview=False)
        image_bytes = files.image.stat().st_size
        started = time.perf_counter()
        report = deploy(files, profile, password=password, link=link, timeout=60.0, confirm_timeout=60.0)
        total = time.perf_counter() - started
        runs.append({**report.timings, "total": total})
        shutil.rmtree(work / f"v{i}")
    med = {key: statistics.median(r[key] for r in runs) for key in (*STEPS, "total")}
    return {"size": size, "bytes": image_bytes, "median": med, "runs": len(runs)}


@contextlib.contextmanager
def openssh() -> Iterator[Any]:
    from tests.fixtures_ssh import running_sshd

    with running_sshd() as server:
        yield server


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="500 and 1000 cells, one run each")
    args = parser.parse_args()
    sizes = (500, 1000) if args.quick else (1000, 4000)
    repeats = 1 if args.quick else 3
    rows: list[tuple[str, dict[str, Any]]] = []
    notes: list[str] = []
    with tempfile.TemporaryDirectory(prefix="pmk-bench-deploy-") as tmp:
        work = Path(tmp)
        sim = SimChair(
            grid=building_grid(200, seed=0), sftp_port=0, maps_dir=work / "chair", scan_rate=5.0, odom_rate=10.0
        ).start()
        link = ChairLink("127.0.0.1", sim.port)
        try:
            link.connect(timeout=10.0)
            profile = ChairProfile(
                name="bench",
                host="127.0.0.1",
                port=sim.port,
                ssh_user=sim.sftp_user,
                ssh_port=sim.sftp_port or 0,
                known_hosts=str(work / "kh"),
            )
            for service in ("/change_map", "/map_update"):
                chosen = dataclasses.replace(profile, reload_service=service)
                for size in sizes:
                    print(f"sim SFTP {service} {size}x{size} ...", flush=True)
                    row = run_case(sim, link, chosen, sim.sftp_password, size, repeats, work)
                    rows.append((f"sim SFTP (asyncssh), {service}", row))
            try:
                with openssh() as server:
                    remote = f"~/pmk-bench/{uuid.uuid4().hex[:8]}/ALMA_MAPS"
                    real = ChairProfile(
                        name="bench-openssh",
                        host="127.0.0.1",
                        port=sim.port,
                        ssh_user=server.user,
                        ssh_port=server.port,
                        auth="key",
                        key_file=str(server.client_key),
                        known_hosts=str(work / "kh2"),
                        remote_maps_dir=remote,
                    )
                    try:
                        for size in sizes:
                            print(f"OpenSSH {size}x{size} ...", flush=True)
                            rows.append(
                                ("OpenSSH sshd, /change_map", run_case(sim, link, real, None, size, repeats, work))
                            )
                    finally:
                        shutil.rmtree(server.home / remote.split("/")[1] / remote.split("/")[2], ignore_errors=True)
            except Exception as err:  # the bench still reports the sim figures
                notes.append(f"OpenSSH case not run: {err}")
        finally:
            link.close()
            sim.stop()
    lines = [
        "## Deploy (upload + detect + reload + confirmed)",
        "",
        f"Median of {repeats} run(s) per case; 0.05 m maps, 8-bit PGM; simulator map server on 127.0.0.1,",
        "reached through the real ChairLink (roslibpy). Times in seconds. LoadMap (/change_map, Nav2",
        "load_map) answers with the whole loaded map, so its reply carries every cell through rosbridge;",
        "MapUpdate answers a bool. For 4000x4000 the reload is dominated by the simulator's own load work",
        "(reading the PGM and, for LoadMap, the client parsing the 35 MB reply), not by the transfer.",
        "",
        "| SFTP server, reload service | map | image MB | upload | detect | reload | confirm | total | upload MB/s |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for server_name, row in rows:
        med, mb = row["median"], row["bytes"] / 1e6
        lines.append(
            f"| {server_name} | {row['size']}x{row['size']} | {mb:.1f} | {med['upload']:.2f} | {med['detect']:.2f} "
            f"| {med['reload']:.2f} | {med['confirm']:.2f} | {med['total']:.2f} | {mb / max(med['upload'], 1e-9):.1f} |"
        )
    lines += [f"\nNote: {n}" for n in notes]
    out = ROOT / "bench" / "results-deploy.md"
    tmp_out = out.with_suffix(".md.tmp")
    tmp_out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    tmp_out.replace(out)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
