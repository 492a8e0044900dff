"""``pmk robot``: the chair-side ROS 2 nodes (run them where rclpy and our interfaces are installed).

- ``pmk robot map-server [--maps-dir DIR] [--map NAME]``: the PMK map server (see pmk_nb.robot.mapserver);
- ``pmk robot sim-node``: the simulated chair behind real rclpy topics (see pmk_nb.robot.simnode);
- ``pmk robot goal-watchdog [--silence S] [--ros1]``: cancels navigation goals when the dashboard's
  heartbeat stops (see pmk_nb.robot.goalwatch).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import overload

from pmk_nb.cli.options import Subparsers, add_maps_dir
from pmk_nb.errors import RosNotInstalled
from pmk_nb.robot import DEFAULT_MAPS


def add_parser(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "robot", help="chair-side ROS nodes: the PMK map server, the simulated chair, the goal watchdog"
    )
    sub = p.add_subparsers(dest="node", metavar="NODE", required=True)
    ms = sub.add_parser(
        "map-server",
        help="the PMK map server: /map, /map_metadata, MapUpdate, Nav2 LoadMap, MapInfo",
        description="Publishes a map from the maps folder and reloads it on request (ROS 2, rclpy).",
    )
    add_maps_dir(ms, aliases=("--maps",), default=DEFAULT_MAPS, help=f"maps folder (default {DEFAULT_MAPS})")
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
    add_maps_dir(sn, aliases=("--maps",), default=DEFAULT_MAPS, help="where the world map is read from")
    sn.add_argument("--map", default=None, help="world map (NAME in --maps-dir or a YAML path); default: a demo floor")
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
    _add_goal_watchdog(sub)


def _add_goal_watchdog(sub: Subparsers) -> None:
    from pmk_nb.goalbeat import SILENCE_S, TOPIC
    from pmk_nb.robot import ACTIONS, CANCEL_TOPIC

    gw = sub.add_parser(
        "goal-watchdog",
        help="cancel navigation goals when the dashboard's goal heartbeat falls silent",
        description="Runs beside Nav2 (rclpy) or move_base (--ros1, rospy). A bridge may keep a lost "
        "client's goals alive; this node ends them when the dashboard that sent them stops beating.",
    )
    gw.add_argument("--silence", type=float, default=SILENCE_S, help=f"seconds of silence (default {SILENCE_S:g})")
    gw.add_argument("--topic", default=TOPIC, help=f"heartbeat topic (default {TOPIC})")
    gw.add_argument(
        "--actions", default=",".join(ACTIONS), help=f"ROS 2 actions to cancel (default {','.join(ACTIONS)})"
    )
    gw.add_argument("--cancel-topic", default=CANCEL_TOPIC, help=f"--ros1: actionlib cancel topic ({CANCEL_TOPIC})")
    gw.add_argument("--ros1", action="store_true", help="the rospy node for move_base, with the system Python")
    gw.set_defaults(run=run_goal_watchdog)


ROS2_HINT = (
    "Run it where ROS 2 is installed and sourced (`source /opt/ros/jazzy/setup.bash`, with Nav2 for "
    "nav2_msgs), or with the test stack this project builds: `make ros2`, then ~/.cache/pmk-ros's venv."
)


def run_ros2(command: str, node: Callable[[], int]) -> int:
    """``node()``, with a missing ROS module said as what to install instead of a ModuleNotFoundError."""
    try:
        return node()
    except ModuleNotFoundError as err:
        missing = err.name or "rclpy"
        if missing.startswith("pmk_nb"):
            raise  # our own bug, not a missing ROS install
        raise RosNotInstalled(
            f"pmk robot {command} needs ROS 2, and Python module {missing!r} is not installed here",
            module=missing,
            command=command,
            hint=ROS2_HINT,
        ) from err


@overload
def _map_request(name: str) -> str: ...
@overload
def _map_request(name: None) -> None: ...
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
    return run_ros2(
        "map-server", lambda: mapserver.run(args.maps_dir, _map_request(args.map), services, cells, without)
    )


def _exec_ros1_map_server(args: argparse.Namespace) -> int:
    """Replace this process by the rospy node under the system Python (rospy is not in the venv)."""
    argv = ["--maps", str(args.maps_dir)]
    argv += ["--map", _map_request(args.map)] if args.map else []
    argv += ["--reply-map-cells", str(args.reply_map_cells)] if args.reply_map_cells is not None else []
    return _exec_ros1("map-server", "pmk_nb.robot.ros1_mapserver", argv)


def _exec_ros1(command: str, module: str, argv: list[str]) -> int:
    """Replace this process by ``module`` under the system Python that has Debian's rospy."""
    import os

    import pmk_nb
    from pmk_nb.robot import ros1_mapserver as ros1

    if not os.access(ros1.SYSTEM_PYTHON, os.X_OK):
        raise SystemExit(f"pmk robot {command} --ros1: {ros1.SYSTEM_PYTHON} not found (install python3-rospy)")
    root = str(Path(pmk_nb.__file__).resolve().parent.parent)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (root, os.environ.get("PYTHONPATH")) if p)}
    os.execve(ros1.SYSTEM_PYTHON, [ros1.SYSTEM_PYTHON, "-m", module, *argv], env)
    return 0  # pragma: no cover - execve does not return


def run_goal_watchdog(args: argparse.Namespace) -> int:
    if args.silence <= 0:
        raise SystemExit(f"pmk robot goal-watchdog: --silence must be > 0 s, got {args.silence:g}")
    if args.ros1:
        argv = ["--silence", str(args.silence), "--topic", args.topic, "--cancel-topic", args.cancel_topic]
        return _exec_ros1("goal-watchdog", "pmk_nb.robot.watchdog_ros1", argv)
    from pmk_nb.robot import watchdog_ros2

    actions = tuple(a.strip() for a in args.actions.split(",") if a.strip())
    if not actions or not all(a.startswith("/") for a in actions):
        raise SystemExit(f"pmk robot goal-watchdog: --actions takes absolute action names, got {args.actions!r}")
    return run_ros2("goal-watchdog", lambda: watchdog_ros2.run(args.silence, actions, args.topic))


def run_sim_node(args: argparse.Namespace) -> int:
    from pmk_nb.robot import simnode

    x, y, yaw = (float(v) for v in args.laser_offset.split(","))
    return run_ros2(
        "sim-node",
        lambda: simnode.run(
            args.maps_dir,
            _map_request(args.map),
            odom_rate=args.odom_rate,
            scan_rate=args.scan_rate,
            laser_offset=(x, y, yaw),
            follow_map=not args.no_follow_map,
            map_odom=not args.no_map_odom,
            rays=args.rays,
        ),
    )
