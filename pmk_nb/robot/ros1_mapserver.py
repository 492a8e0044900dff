"""The PMK map server as a ROS 1 node (rospy): the original chair ran ROS 1 (``map_server_pmk``).

Runs with the system Python that has Debian's ``python3-rospy`` (``/usr/bin/python3``), not the
project's venv: it imports only the standard library, rospy, Debian's message packages and the
project's pure map store (numpy, yaml, PIL), found through ``PYTHONPATH``. Same store, reader and
metadata filling as the ROS 2 node (:mod:`pmk_nb.robot.mapstore`, ``mapserver.fill_info``, whose
module imports rclpy only when that node runs), so both publish exactly what the dashboard previewed.

Topics ``/map`` and ``/map_metadata`` (latched). Services:

- ``/change_map`` (``nav_msgs/LoadMap``, as ROS 1's map_server): result 0, anything else 255;
- ``/map_update`` (``map_server_pmk/MapUpdate``): ``string path`` -> ``bool done``, as the original;
- ``/map_server/map_info`` (``map_server_pmk/MapInfo``): header, metadata, SHA-256, YAML path;
- ``/static_map`` (``nav_msgs/GetMap``), as ROS 1's map_server.

Our two services have no Debian package: genpy generates their Python classes at start from the
service texts below (the same as ``ros/interfaces/map_server_pmk/srv/*.srv``, checked by a test).

Run: ``PYTHONPATH=<checkout> /usr/bin/python3 -m pmk_nb.robot.ros1_mapserver --maps DIR [--map NAME]``
(``pmk robot map-server --ros1`` does exactly that).
"""

from __future__ import annotations

import argparse
import sys
import threading
import types
from pathlib import Path
from typing import Any

from pmk_nb.robot.mapserver import fill_info  # rclpy is imported there only when the ROS 2 node runs
from pmk_nb.robot.mapstore import DEFAULT_MAPS, LoadedMap, MapStore
from pmk_nb.wire import ros1_result

READY_LINE = "pmk robot map-server --ros1: ready"
SYSTEM_PYTHON = "/usr/bin/python3"
REPLY_MAP_CELLS = 4_000_000  # as the ROS 2 node: bigger grids are confirmed with map_info

#: The service texts genpy generates classes from (identical to ros/interfaces/map_server_pmk/srv).
SRV_TEXTS: dict[str, str] = {
    "MapUpdate": "string path\n---\nbool done\n",
    "MapInfo": "---\nbool loaded\nstd_msgs/Header header\nnav_msgs/MapMetaData info\nstring sha256\nstring path\n",
}
#: Where Debian's ROS 1 message definitions live (genpy resolves Header and MapMetaData there).
MSG_SEARCH_PATH: dict[str, list[str]] = {
    pkg: [f"/usr/share/{pkg}/msg"] for pkg in ("std_msgs", "nav_msgs", "geometry_msgs")
}


def generate_srv(name: str, package: str = "map_server_pmk") -> Any:
    """The rospy service class for ``SRV_TEXTS[name]``, generated with genpy as ``genpy`` would at build time."""
    import genmsg
    import genmsg.msg_loader
    import genpy.generator

    context = genmsg.MsgContext.create_default()
    spec = genmsg.msg_loader.load_srv_from_string(context, SRV_TEXTS[name], f"{package}/{name}")
    code = "\n".join(genpy.generator.srv_generator(context, spec, MSG_SEARCH_PATH))
    module = types.ModuleType(f"{package}.srv._{name}")
    sys.modules[module.__name__] = module  # genpy's classes look their module up when pickled / printed
    exec(compile(code, f"<genpy {package}/{name}>", "exec"), module.__dict__)  # genpy's output
    return getattr(module, name)


def srv_response(srv: Any) -> Any:
    """The response class genpy generated beside the service class ``srv`` (``NAMEResponse``, public in
    its module; the service class's own ``_response_class`` is genpy's private spelling of it)."""
    return getattr(sys.modules[srv.__module__], f"{srv.__name__}Response")


def grid_msg(loaded: LoadedMap, stamp: Any, *, numpy_cells: bool) -> Any:
    """A nav_msgs/OccupancyGrid of a loaded map.

    ``numpy_cells``: a ``numpy_msg(OccupancyGrid)`` whose cells stay one int8 array that genpy writes
    in one go (the /map publisher: 16 M cells in milliseconds); else a plain message with the cells as
    a list, the only form genpy packs inside a service reply.
    """
    from nav_msgs.msg import OccupancyGrid
    from rospy.numpy_msg import numpy_msg

    msg = numpy_msg(OccupancyGrid)() if numpy_cells else OccupancyGrid()
    msg.header.frame_id = loaded.grid.frame_id or "map"
    msg.header.stamp = stamp
    fill_info(msg.info, loaded, stamp)
    cells = loaded.grid.data.astype("int8", copy=False).ravel()
    msg.data = cells if numpy_cells else cells.tolist()
    return msg


class Ros1MapServer:
    """Publishers, services and the store of one rospy map server (rospy runs callbacks on its threads)."""

    def __init__(self, store: MapStore, reply_map_cells: int = REPLY_MAP_CELLS) -> None:
        import rospy
        from nav_msgs.msg import MapMetaData, OccupancyGrid
        from nav_msgs.srv import GetMap, LoadMap
        from rospy.numpy_msg import numpy_msg

        self.rospy = rospy
        self.store = store
        self.reply_map_cells = reply_map_cells
        self.cache: dict[str, Any] = {}
        self.lock = threading.Lock()  # rospy runs each service call on its own thread
        self.map_pub = rospy.Publisher("/map", numpy_msg(OccupancyGrid), queue_size=1, latch=True)
        self.meta_pub = rospy.Publisher("/map_metadata", MapMetaData, queue_size=1, latch=True)
        self.map_update_srv, self.map_info_srv = generate_srv("MapUpdate"), generate_srv("MapInfo")
        self.services = [
            rospy.Service("/change_map", LoadMap, self.change_map),
            rospy.Service("/map_update", self.map_update_srv, self.map_update),
            rospy.Service("/map_server/map_info", self.map_info_srv, self.map_info),
            rospy.Service("/static_map", GetMap, self.static_map),
        ]

    def load(self, request: str) -> int:
        """Load and publish; returns Nav2's result code (0 = loaded)."""
        code, text = self.store.load(request)
        if code != 0:
            self.rospy.logwarn(text)
            return code
        self.rospy.loginfo(text)
        self.publish()
        return 0

    def publish(self) -> None:
        from nav_msgs.msg import MapMetaData

        loaded = self.store.current
        if loaded is None:
            return
        stamp = self.rospy.Time.now()
        meta = MapMetaData()
        fill_info(meta, loaded, stamp)
        with self.lock:
            self.cache.update(stamp=stamp, loaded=loaded, msg=None)  # the list form: built when a reply needs it
            self.map_pub.publish(grid_msg(loaded, stamp, numpy_cells=True))
        self.meta_pub.publish(meta)

    # -- service callbacks (rospy threads) --------------------------------------------------------
    def change_map(self, request: Any) -> Any:
        from nav_msgs.srv import LoadMapResponse

        code = self.load(request.map_url)
        response = LoadMapResponse(result=ros1_result(code))
        loaded = self.cache.get("loaded")
        if code == 0 and loaded is not None and loaded.grid.data.size <= self.reply_map_cells:
            response.map = self.reply_map()
        return response

    def reply_map(self) -> Any:
        """The current map as a plain message for a service reply (built once per map)."""
        with self.lock:
            if self.cache.get("msg") is None:
                self.cache["msg"] = grid_msg(self.cache["loaded"], self.cache["stamp"], numpy_cells=False)
            return self.cache["msg"]

    def map_update(self, request: Any) -> Any:
        return srv_response(self.map_update_srv)(done=self.load(request.path) == 0)

    def map_info(self, _request: Any) -> Any:
        response = srv_response(self.map_info_srv)()
        loaded = self.cache.get("loaded")
        response.loaded = loaded is not None
        if loaded is not None:
            response.header.frame_id = loaded.grid.frame_id or "map"
            response.header.stamp = self.cache["stamp"]
            fill_info(response.info, loaded, self.cache["stamp"])
            response.sha256, response.path = loaded.sha256, str(loaded.path)
        return response

    def static_map(self, _request: Any) -> Any:
        from nav_msgs.srv import GetMapResponse

        return GetMapResponse(map=self.reply_map()) if "loaded" in self.cache else GetMapResponse()


def run(maps_dir: Path, first_map: str | None, reply_map_cells: int = REPLY_MAP_CELLS) -> int:
    """Start the node (ROS_MASTER_URI from the environment) and spin; prints READY_LINE when offered."""
    import rospy

    rospy.init_node("map_server", disable_signals=False)
    server = Ros1MapServer(MapStore(maps_dir), reply_map_cells)
    if first_map and server.load(first_map) != 0:
        rospy.logerr(f"could not load the first map {first_map!r}")
    print(READY_LINE, flush=True)
    rospy.spin()
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="pmk robot map-server --ros1", description=__doc__.splitlines()[0])
    ap.add_argument("--maps", type=Path, default=DEFAULT_MAPS)
    ap.add_argument("--map", default=None, help="map to publish at start (a YAML in the maps folder)")
    ap.add_argument("--reply-map-cells", type=int, default=REPLY_MAP_CELLS)
    args = ap.parse_args(argv)
    return run(args.maps, args.map, args.reply_map_cells)


if __name__ == "__main__":
    raise SystemExit(main())
