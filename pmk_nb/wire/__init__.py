"""What crosses the wire to the chair, written once (issue 42): the link (``chair/``), the simulated
chair (``sim/``), the chair-side nodes (``robot/``) and the live view's maths (``viewport/``) all speak it.

``angles`` (yaw wrapped to (-pi, pi], yaw <-> quaternion), ``shapes`` (stamps and type spellings of
both ROS versions, the pose dict), ``actions`` (Nav2's and move_base's actions: names, types, goal
status and cancel codes), ``loadmap`` (a map server's reload answer: the LoadMap result codes, how a
failed load becomes one), ``gridhash`` (the grid SHA-256 that confirms a deploy) and ``raycast`` (the one
ray caster: the simulator's laser and the live view's map cast are thin adapters on it).

A leaf: it imports nothing of pmk_nb but ``errors``, ``grid`` (for types) and ``lazyface``, so both ends of the
wire can use it without one depending on the other.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.wire.actions import (
        ACTIONLIB_ABORTED,
        ACTIONLIB_ACTIVE,
        ACTIONLIB_LOST,
        ACTIONLIB_PENDING,
        ACTIONLIB_PREEMPTED,
        ACTIONLIB_PREEMPTING,
        ACTIONLIB_RECALLED,
        ACTIONLIB_RECALLING,
        ACTIONLIB_REJECTED,
        ACTIONLIB_SUCCEEDED,
        CANCEL_ERROR_GOAL_TERMINATED,
        CANCEL_ERROR_NONE,
        CANCEL_ERROR_REJECTED,
        CANCEL_ERROR_UNKNOWN_GOAL_ID,
        CANCEL_GOAL_TYPE,
        GOAL_STATUS_ARRAY,
        MOVE_BASE,
        MOVE_BASE_CANCEL,
        NAV2_ACTION,
        NAV2_ACTIONS,
        NAV2_THROUGH,
        STATUS_ABORTED,
        STATUS_ACCEPTED,
        STATUS_CANCELED,
        STATUS_CANCELING,
        STATUS_EXECUTING,
        STATUS_SUCCEEDED,
        STATUS_UNKNOWN,
    )
    from pmk_nb.wire.angles import (
        quaternion_from_yaw,
        wrap_angle,
        yaw_from_quaternion,
    )
    from pmk_nb.wire.gridhash import (
        grid_sha256,
    )
    from pmk_nb.wire.loadmap import (
        INVALID_MAP_DATA,
        INVALID_MAP_METADATA,
        LOAD_SUCCESS,
        MAP_DOES_NOT_EXIST,
        UNDEFINED_FAILURE,
        LoadAnswer,
        empty_request,
        load_failure,
        ros1_result,
    )
    from pmk_nb.wire.raycast import (
        FIRST_BLOCK,
        MAX_BLOCK,
        CellsOf,
        first_hits,
    )
    from pmk_nb.wire.shapes import (
        ROS2_KINDS,
        is_type_name,
        make_stamp,
        normalise_type,
        pose_msg,
        spell_type,
        stamp_ros_version,
        stamp_to_sec,
        type_ros_version,
        type_spellings,
        vec3,
    )

_WHERE = {
    "ACTIONLIB_ABORTED": "actions",
    "ACTIONLIB_ACTIVE": "actions",
    "ACTIONLIB_LOST": "actions",
    "ACTIONLIB_PENDING": "actions",
    "ACTIONLIB_PREEMPTED": "actions",
    "ACTIONLIB_PREEMPTING": "actions",
    "ACTIONLIB_RECALLED": "actions",
    "ACTIONLIB_RECALLING": "actions",
    "ACTIONLIB_REJECTED": "actions",
    "ACTIONLIB_SUCCEEDED": "actions",
    "CANCEL_ERROR_GOAL_TERMINATED": "actions",
    "CANCEL_ERROR_NONE": "actions",
    "CANCEL_ERROR_REJECTED": "actions",
    "CANCEL_ERROR_UNKNOWN_GOAL_ID": "actions",
    "CANCEL_GOAL_TYPE": "actions",
    "GOAL_STATUS_ARRAY": "actions",
    "MOVE_BASE": "actions",
    "MOVE_BASE_CANCEL": "actions",
    "NAV2_ACTION": "actions",
    "NAV2_ACTIONS": "actions",
    "NAV2_THROUGH": "actions",
    "STATUS_ABORTED": "actions",
    "STATUS_ACCEPTED": "actions",
    "STATUS_CANCELED": "actions",
    "STATUS_CANCELING": "actions",
    "STATUS_EXECUTING": "actions",
    "STATUS_SUCCEEDED": "actions",
    "STATUS_UNKNOWN": "actions",
    "quaternion_from_yaw": "angles",
    "wrap_angle": "angles",
    "yaw_from_quaternion": "angles",
    "grid_sha256": "gridhash",
    "INVALID_MAP_DATA": "loadmap",
    "INVALID_MAP_METADATA": "loadmap",
    "LOAD_SUCCESS": "loadmap",
    "LoadAnswer": "loadmap",
    "MAP_DOES_NOT_EXIST": "loadmap",
    "UNDEFINED_FAILURE": "loadmap",
    "empty_request": "loadmap",
    "load_failure": "loadmap",
    "ros1_result": "loadmap",
    "CellsOf": "raycast",
    "FIRST_BLOCK": "raycast",
    "MAX_BLOCK": "raycast",
    "first_hits": "raycast",
    "ROS2_KINDS": "shapes",
    "is_type_name": "shapes",
    "make_stamp": "shapes",
    "normalise_type": "shapes",
    "pose_msg": "shapes",
    "spell_type": "shapes",
    "stamp_ros_version": "shapes",
    "stamp_to_sec": "shapes",
    "type_ros_version": "shapes",
    "type_spellings": "shapes",
    "vec3": "shapes",
}

__all__ = [
    "ACTIONLIB_ABORTED",
    "ACTIONLIB_ACTIVE",
    "ACTIONLIB_LOST",
    "ACTIONLIB_PENDING",
    "ACTIONLIB_PREEMPTED",
    "ACTIONLIB_PREEMPTING",
    "ACTIONLIB_RECALLED",
    "ACTIONLIB_RECALLING",
    "ACTIONLIB_REJECTED",
    "ACTIONLIB_SUCCEEDED",
    "CANCEL_ERROR_GOAL_TERMINATED",
    "CANCEL_ERROR_NONE",
    "CANCEL_ERROR_REJECTED",
    "CANCEL_ERROR_UNKNOWN_GOAL_ID",
    "CANCEL_GOAL_TYPE",
    "FIRST_BLOCK",
    "GOAL_STATUS_ARRAY",
    "INVALID_MAP_DATA",
    "INVALID_MAP_METADATA",
    "LOAD_SUCCESS",
    "MAP_DOES_NOT_EXIST",
    "MAX_BLOCK",
    "MOVE_BASE",
    "MOVE_BASE_CANCEL",
    "NAV2_ACTION",
    "NAV2_ACTIONS",
    "NAV2_THROUGH",
    "ROS2_KINDS",
    "STATUS_ABORTED",
    "STATUS_ACCEPTED",
    "STATUS_CANCELED",
    "STATUS_CANCELING",
    "STATUS_EXECUTING",
    "STATUS_SUCCEEDED",
    "STATUS_UNKNOWN",
    "UNDEFINED_FAILURE",
    "CellsOf",
    "LoadAnswer",
    "empty_request",
    "first_hits",
    "grid_sha256",
    "is_type_name",
    "load_failure",
    "make_stamp",
    "normalise_type",
    "pose_msg",
    "quaternion_from_yaw",
    "ros1_result",
    "spell_type",
    "stamp_ros_version",
    "stamp_to_sec",
    "type_ros_version",
    "type_spellings",
    "vec3",
    "wrap_angle",
    "yaw_from_quaternion",
]


__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
