"""The message definitions the simulated bridge can describe, as rosapi's ``message_details`` answers.

A real bridge describes every type installed on the chair; the simulator knows the types it publishes,
those clients commonly publish through it (RViz markers, ``std_msgs`` scalars) and their dependencies.
Each type's own fields are written once in ``.msg`` form (ROS 2 Humble spellings, kept independent of
the link's bundled definitions); :func:`typedefs` turns them into rosapi ``TypeDef`` dicts for either
ROS version, as rosapi builds them:

* ROS 1 (rosapi 1.x): primitives spelled as in ``.msg`` (``float64``), stamps as the specials ``time``
  / ``duration`` (with their own ``{secs, nsecs}`` typedef), ``std_msgs/Header`` with ``seq``, and no
  ROS 2-only fields (a Noetic ``Marker`` has no texture or mesh file).
* ROS 2 (rosapi 2.x): IDL spellings (``double``, ``float``, ``boolean``, ``octet``), stamps as
  ``builtin_interfaces/Time``.

Arrays: ``fieldarraylen`` -1 for a single value, 0 for a sequence, N for a fixed array. A type the
bridge does not know: ``None`` (rosapi 1.x fails the call; 2.x answers no typedefs).
"""

from __future__ import annotations

from typing import Any

from pmk_nb.wire import normalise_type as canonical_type

#: each message's own fields and constants (``pkg/Type`` field types)
FIELDS: dict[str, str] = {
    "builtin_interfaces/Time": "int32 sec\nuint32 nanosec\n",
    "builtin_interfaces/Duration": "int32 sec\nuint32 nanosec\n",
    "std_msgs/Header": "builtin_interfaces/Time stamp\nstring frame_id\n",
    "std_msgs/String": "string data\n",
    "std_msgs/Int32": "int32 data\n",
    "std_msgs/Float64": "float64 data\n",
    "std_msgs/Bool": "bool data\n",
    "std_msgs/ColorRGBA": "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n",
    "geometry_msgs/Point": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/Vector3": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/Quaternion": "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
    "geometry_msgs/Pose": "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
    "geometry_msgs/PoseStamped": "std_msgs/Header header\ngeometry_msgs/Pose pose\n",
    "geometry_msgs/PoseWithCovariance": "geometry_msgs/Pose pose\nfloat64[36] covariance\n",
    "geometry_msgs/PoseWithCovarianceStamped": "std_msgs/Header header\ngeometry_msgs/PoseWithCovariance pose\n",
    "geometry_msgs/Point32": "float32 x\nfloat32 y\nfloat32 z\n",
    "geometry_msgs/Polygon": "geometry_msgs/Point32[] points\n",
    "geometry_msgs/PolygonStamped": "std_msgs/Header header\ngeometry_msgs/Polygon polygon\n",
    "geometry_msgs/Twist": "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n",
    "geometry_msgs/TwistStamped": "std_msgs/Header header\ngeometry_msgs/Twist twist\n",
    "geometry_msgs/TwistWithCovariance": "geometry_msgs/Twist twist\nfloat64[36] covariance\n",
    "geometry_msgs/Transform": "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n",
    "geometry_msgs/TransformStamped": (
        "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"
    ),
    "tf2_msgs/TFMessage": "geometry_msgs/TransformStamped[] transforms\n",
    "nav_msgs/Odometry": (
        "std_msgs/Header header\nstring child_frame_id\n"
        "geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n"
    ),
    "nav_msgs/Path": "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n",
    "nav_msgs/MapMetaData": (
        "builtin_interfaces/Time map_load_time\nfloat32 resolution\nuint32 width\nuint32 height\n"
        "geometry_msgs/Pose origin\n"
    ),
    "nav_msgs/OccupancyGrid": "std_msgs/Header header\nnav_msgs/MapMetaData info\nint8[] data\n",
    "map_msgs/OccupancyGridUpdate": (
        "std_msgs/Header header\nint32 x\nint32 y\nuint32 width\nuint32 height\nint8[] data\n"
    ),
    "sensor_msgs/LaserScan": (
        "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
        "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n"
        "float32[] ranges\nfloat32[] intensities\n"
    ),
    "sensor_msgs/CompressedImage": "std_msgs/Header header\nstring format\nuint8[] data\n",
    "visualization_msgs/UVCoordinate": "float32 u\nfloat32 v\n",
    "visualization_msgs/MeshFile": "string filename\nuint8[] data\n",
    "visualization_msgs/Marker": (
        "int32 ARROW=0\nint32 CUBE=1\nint32 SPHERE=2\nint32 CYLINDER=3\nint32 LINE_STRIP=4\n"
        "int32 LINE_LIST=5\nint32 CUBE_LIST=6\nint32 SPHERE_LIST=7\nint32 POINTS=8\n"
        "int32 TEXT_VIEW_FACING=9\nint32 MESH_RESOURCE=10\nint32 TRIANGLE_LIST=11\n"
        "int32 ADD=0\nint32 MODIFY=0\nint32 DELETE=2\nint32 DELETEALL=3\n"
        "std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\n"
        "geometry_msgs/Pose pose\ngeometry_msgs/Vector3 scale\nstd_msgs/ColorRGBA color\n"
        "builtin_interfaces/Duration lifetime\nbool frame_locked\n"
        "geometry_msgs/Point[] points\nstd_msgs/ColorRGBA[] colors\n"
        "string texture_resource\nsensor_msgs/CompressedImage texture\n"
        "visualization_msgs/UVCoordinate[] uv_coordinates\n"
        "string text\nstring mesh_resource\nvisualization_msgs/MeshFile mesh_file\n"
        "bool mesh_use_embedded_materials\n"
    ),
    "visualization_msgs/MarkerArray": "visualization_msgs/Marker[] markers\n",
}
#: fields a ROS 1 (Noetic) message does not have
ROS2_ONLY: dict[str, frozenset[str]] = {
    "visualization_msgs/Marker": frozenset({"texture_resource", "texture", "uv_coordinates", "mesh_file"}),
}
#: ``.msg`` primitive -> the IDL name rosapi 2.x reports
IDL = {"float64": "double", "float32": "float", "bool": "boolean", "byte": "octet", "char": "uint8"}
SPECIALS = {"builtin_interfaces/Time": "time", "builtin_interfaces/Duration": "duration"}


def _lines(type_key: str, ros: str) -> tuple[list[tuple[str, str, int]], list[tuple[str, str]]]:
    """(fields as (name, type, arraylen), constants as (name, value)) of one type."""
    fields: list[tuple[str, str, int]] = []
    consts: list[tuple[str, str]] = []
    if ros == "ros1" and type_key == "std_msgs/Header":
        fields.append(("seq", "uint32", -1))
    for line in FIELDS[type_key].splitlines():
        kind, rest = line.split(None, 1)
        if "=" in rest:
            name, value = rest.split("=", 1)
            consts.append((name.strip(), value.strip()))
            continue
        if ros == "ros1" and rest in ROS2_ONLY.get(type_key, ()):
            continue
        base, bracket, size = kind.partition("[")
        arraylen = int(size.rstrip("]") or 0) if bracket else -1
        base = SPECIALS.get(base, base) if ros == "ros1" else IDL.get(base, base)
        fields.append((rest, base, arraylen))
    return fields, consts


def _typedef(type_key: str, ros: str) -> dict[str, Any]:
    if type_key in ("time", "duration"):
        fields = [("secs", "int32", -1), ("nsecs", "int32", -1)]
        consts: list[tuple[str, str]] = []
    else:
        fields, consts = _lines(type_key, ros)
    return {
        "type": type_key,
        "fieldnames": [f[0] for f in fields],
        "fieldtypes": [f[1] for f in fields],
        "fieldarraylen": [f[2] for f in fields],
        "examples": ["[]" if f[2] >= 0 else ("{}" if "/" in f[1] else "0") for f in fields],
        "constnames": [c[0] for c in consts],
        "constvalues": [c[1] for c in consts],
    }


def typedefs(type_name: str, ros: str) -> list[dict[str, Any]] | None:
    """rosapi's ``message_details`` typedefs for ``type_name`` (any spelling): the type first, then each
    type it uses once, depth-first; None when the simulator does not know it."""
    root = canonical_type(type_name)
    if root not in FIELDS:
        return None
    seen: list[str] = []

    def walk(type_key: str) -> None:
        seen.append(type_key)
        for field_type in _typedef(type_key, ros)["fieldtypes"]:
            if (field_type in FIELDS or field_type in ("time", "duration")) and field_type not in seen:
                walk(field_type)

    walk(root)
    return [_typedef(t, ros) for t in seen]
