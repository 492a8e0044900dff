"""The rosapi services clients use for discovery, answered from the bridge's own registry.

Shapes follow rosapi: ``/rosapi/topics`` -> ``{topics, types}``, ``/rosapi/services`` ->
``{services}``, ``/rosapi/topic_type`` -> ``{type}`` ("" when unknown), ``/rosapi/get_time`` ->
``{time: {secs, nsecs}}`` (ROS 2: ``{sec, nanosec}``), ``/rosapi/topics_for_type`` -> ``{topics}``,
``/rosapi/service_type`` -> ``{type}``, ``/rosapi/services_for_type`` -> ``{services}``,
``/rosapi/nodes`` -> ``{nodes}``, (ROS 2) ``/rosapi/action_servers`` -> ``{action_servers}``,
``/rosapi/get_ros_version`` -> ``{version, distro}``, ``/rosapi/message_details`` -> ``{typedefs}``
(:mod:`pmk_nb.sim.typedefs`), ``/rosapi/get_param`` (name ``node:param``)
-> ``{value}`` (JSON text; the default when not set). The nodes and the bridge's own parameter
follow the bridge mode (:mod:`pmk_nb.sim.bridge_modes`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from pmk_nb.sim.bridge_modes import NEW_THREAD_PARAM, OFFICIAL_NODE
from pmk_nb.sim.messages import Names, canonical_type
from pmk_nb.sim.typedefs import typedefs

if TYPE_CHECKING:
    from pmk_nb.sim.protocol import Bridge

NODES = ("/rosbridge_websocket", "/rosapi", "/map_server", "/pmk_sim")
CHAIR_NODES = ("/map_server", "/pmk_sim")


def register_rosapi(bridge: Bridge, names: Names, clock: Callable[[], float]) -> None:
    pkg = "rosapi" if names.ros == "ros1" else "rosapi_msgs"

    def add(service: str, type_name: str, answer: Callable[[dict[str, Any]], dict[str, Any]]) -> None:
        async def handler(args: dict[str, Any]) -> tuple[dict[str, Any], bool]:
            return answer(args), True

        bridge.add_service(f"/rosapi/{service}", names.srv(pkg, type_name), handler)

    def topics(_: dict[str, Any]) -> dict[str, Any]:
        items = sorted(bridge.topics.items())
        return {"topics": [n for n, _ in items], "types": [e.type for _, e in items]}

    def topics_for_type(args: dict[str, Any]) -> dict[str, Any]:
        want = canonical_type(str(args.get("type", "")))
        return {"topics": sorted(n for n, e in bridge.topics.items() if canonical_type(e.type) == want)}

    def topic_type(args: dict[str, Any]) -> dict[str, Any]:
        entry = bridge.topics.get(str(args.get("topic", "")))
        return {"type": entry.type if entry else ""}

    def services_for_type(args: dict[str, Any]) -> dict[str, Any]:
        want = canonical_type(str(args.get("type", "")))
        return {"services": sorted(n for n, e in bridge.services.items() if canonical_type(e.type) == want)}

    def service_type(args: dict[str, Any]) -> dict[str, Any]:
        entry = bridge.services.get(str(args.get("service", "")))
        return {"type": entry.type if entry else ""}

    add("topics", "Topics", topics)
    add("topics_for_type", "TopicsForType", topics_for_type)
    add("topic_type", "TopicType", topic_type)
    add("services", "Services", lambda _: {"services": sorted(bridge.services)})
    add("services_for_type", "ServicesForType", services_for_type)
    add("service_type", "ServiceType", service_type)
    add("get_time", "GetTime", lambda _: {"time": names.stamp(clock())})
    add("message_details", "MessageDetails", lambda a: {"typedefs": typedefs(names, str(a.get("type", "")))})
    nodes = NODES if names.ros == "ros1" else (*bridge.bridge_facts.nodes, *CHAIR_NODES)
    add("nodes", "Nodes", lambda _: {"nodes": list(nodes)})
    # rosbridge_suite's launch default; the rs bridge has no such parameter
    params = {f"{OFFICIAL_NODE}:{NEW_THREAD_PARAM}": "false"} if bridge.mode == "official" else {}
    add("get_param", "GetParam", lambda a: {"value": params.get(str(a.get("name")), str(a.get("default_value", "")))})
    if names.ros == "ros2":  # rosapi 2.x: the action servers (Nav2's navigate_to_pose, ...)
        add("action_servers", "GetActionServers", lambda _: {"action_servers": sorted(bridge.actions)})
    add(
        "get_ros_version",
        "GetROSVersion",
        lambda _: {"version": names.ros_version, "distro": "noetic" if names.ros_version == 1 else "humble"},
    )
