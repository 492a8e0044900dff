"""``pmk robot``: the chair-side ROS 2 nodes (run them where rclpy and our interfaces are installed).

- ``pmk robot map-server [--maps DIR] [--map NAME]``: the PMK map server (see pmk_nb.robot.mapserver);
- ``pmk robot sim-node``: the simulated chair behind real rclpy topics (see pmk_nb.robot.simnode).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from pmk_nb.robot.mapstore import DEFAULT_MAPS


def add_parser(subparsers: Any) -> None:
    p = subparsers.add_parser("robot", help="chair-side ROS 2 nodes: the PMK map server, the simulated chair")
    sub = p.add_subparsers(dest="node", metavar="NODE", required=True)
    ms = sub.add_parser(
        "map-server",
        help="the PMK map server: /map, /map_metadata, MapUpdate, Nav2 LoadMap, MapInfo",
        description="Publishes a map from the maps folder and reloads it on request (ROS 2, rclpy).",
    )
    ms.add_argument("--maps", type=Path, default=DEFAULT_MAPS, help=f"maps folder (default {DEFAULT_MAPS})")
    ms.add_argument("--map", default=None, help="map to publish at start: NAME, NAME.yaml or a path in the folder")
    ms.add_argument(
        "--services",
        default="load_map,map_update",
        help="reload services to offer, comma-separated: load_map (Nav2), map_update (PMK), change_map "
        "(ROS 1 style nav_msgs/LoadMap) (default load_map,map_update)",
    )
    ms.add_argument(
        "--reply-map-cells",
        type=int,
        default=None,
        help="LoadMap replies carry the grid up to this many cells (default 4000000; bigger grids make "
        "rosbridge drop the reply: clients confirm with /map_server/map_info)",
    )
    ms.add_argument(
        "--without",
        default="",
        help="leave out, comma-separated: map_metadata (the topic), map_info (the service); both to act "
        "like Nav2's map_server, which has neither",
    )
    ms.add_argument(
        "--ros1",
        action="store_true",
        help="run the ROS 1 (rospy) node instead, with the system Python that has Debian's python3-rospy",
    )
    ms.set_defaults(run=run_map_server)
    sn = sub.add_parser(
        "sim-node",
        help="the simulated chair as a ROS 2 node: /odom, /scan, /tf, /tf_static, /cmd_vel, /goal_pose",
        description="The simulator's physics, laser and tf behind rclpy publishers and subscribers.",
    )
    sn.add_argument("--maps", type=Path, default=DEFAULT_MAPS, help="where the world map is read from")
    sn.add_argument("--map", default=None, help="world map (NAME in --maps or a YAML path); default: a demo floor")
    sn.add_argument("--odom-rate", type=float, default=50.0, help="Hz")
    sn.add_argument("--scan-rate", type=float, default=20.0, help="Hz")
    sn.add_argument("--rays", type=int, default=720, help="laser rays per scan (default 720)")
    sn.add_argument(
        "--laser-offset",
        default="0.25,0.1,0.0",
        help="base_link -> laser as x,y,yaw in metres/radians, on /tf_static (default 0.25,0.1,0.0)",
    )
    sn.add_argument("--no-follow-map", action="store_true", help="keep the world map; ignore /map")
    sn.add_argument(
        "--no-map-odom", action="store_true", help="publish no map->odom (another node localises, e.g. AMCL)"
    )
    sn.set_defaults(run=run_sim_node)


def _map_request(name: str | None) -> str | None:
    if name is None or name.endswith((".yaml", ".yml")):
        return name
    return name + ".yaml"


def run_map_server(args: argparse.Namespace) -> int:
    if args.ros1:
        return _exec_ros1_map_server(args)
    from pmk_nb.robot import mapserver

    services = tuple(s.strip() for s in args.services.split(",") if s.strip())
    unknown = [s for s in services if s not in mapserver.RELOAD_SERVICES]
    if unknown:
        raise SystemExit(
            f"pmk robot map-server: unknown service(s) {unknown}; use {', '.join(mapserver.RELOAD_SERVICES)}"
        )
    without = tuple(s.strip() for s in args.without.split(",") if s.strip())
    if set(without) - set(mapserver.OPTIONAL):
        raise SystemExit(f"pmk robot map-server: --without takes {', '.join(mapserver.OPTIONAL)}")
    cells = mapserver.REPLY_MAP_CELLS if args.reply_map_cells is None else args.reply_map_cells
    return mapserver.run(args.maps, _map_request(args.map), services, cells, without)


def _exec_ros1_map_server(args: argparse.Namespace) -> int:
    """Replace this process by the rospy node under the system Python (rospy is not in the venv)."""
    import os

    import pmk_nb
    from pmk_nb.robot import ros1_mapserver as ros1

    if not os.access(ros1.SYSTEM_PYTHON, os.X_OK):
        raise SystemExit(f"pmk robot map-server --ros1: {ros1.SYSTEM_PYTHON} not found (install python3-rospy)")
    root = str(Path(pmk_nb.__file__).resolve().parent.parent)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (root, os.environ.get("PYTHONPATH")) if p)}
    argv = [ros1.SYSTEM_PYTHON, "-m", "pmk_nb.robot.ros1_mapserver", "--maps", str(args.maps)]
    argv += ["--map", _map_request(args.map)] if args.map else []
    argv += ["--reply-map-cells", str(args.reply_map_cells)] if args.reply_map_cells is not None else []
    os.execve(ros1.SYSTEM_PYTHON, argv, env)
    return 0  # pragma: no cover - execve does not return


def run_sim_node(args: argparse.Namespace) -> int:
    from pmk_nb.robot import simnode

    x, y, yaw = (float(v) for v in args.laser_offset.split(","))
    return simnode.run(
        args.maps,
        _map_request(args.map),
        odom_rate=args.odom_rate,
        scan_rate=args.scan_rate,
        laser_offset=(x, y, yaw),
        follow_map=not args.no_follow_map,
        map_odom=not args.no_map_odom,
        rays=args.rays,
    )
