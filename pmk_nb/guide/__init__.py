"""Guiding the chair by room: rooms of a storey, "you are here", room search, routes and goals.

Pure (no widgets, no network): reads the ``NAME.rooms.json`` sidecar written beside every map
(:mod:`pmk_nb.access.sidecar`) and the map itself, and decides with the accessibility rules of
:mod:`pmk_nb.access` which transitions the chair fits through.

Public API: :func:`load_rooms` / :class:`RoomsMap` (:mod:`.rooms`: ``room_at``, ``search``),
:func:`plan_route` / :class:`Route` (:mod:`.route`), :func:`goal_in_room` (:mod:`.goal`),
:func:`go_to` (:mod:`.visit`: plan and send, for the dashboard and scripts), and the
errors :class:`UnknownRoom` and :class:`NoAccessibleRoute`.
"""

from pmk_nb.guide.errors import NoAccessibleRoute, NoGraph, NotOnMap, RouteError, UnknownRoom
from pmk_nb.guide.goal import goal_in_room
from pmk_nb.guide.rooms import Room, RoomsMap, load_rooms
from pmk_nb.guide.route import Route, plan_route
from pmk_nb.guide.visit import Navigator, chair_xy, go_to

__all__ = [
    "Navigator",
    "NoAccessibleRoute",
    "NoGraph",
    "NotOnMap",
    "Room",
    "RoomsMap",
    "Route",
    "RouteError",
    "UnknownRoom",
    "chair_xy",
    "go_to",
    "goal_in_room",
    "load_rooms",
    "plan_route",
]
