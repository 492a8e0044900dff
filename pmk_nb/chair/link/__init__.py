"""The rosbridge link to one chair (roslibpy), in rooms by concept; this face names what others use.

``client`` holds :class:`ChairLink`, the chair-level verbs, built from a :class:`LinkConfig`
(``linkconfig``) around a small public core (``core.LinkCore``: the Protocol the helpers and the
link's users take; ``roles``: the narrower Protocols some screens take); ``registry`` keeps the
kernel's only set of links (one per chair). Underneath:

* ``transport/``: the socket. ``ros`` (``LinkRos``: roslibpy on a private loop; ``framework`` is the one
  place that picks asyncio or Twisted), ``factory`` / ``factory_twisted``, ``backoff``, ``tls``,
  ``bridge_auth``, ``probe`` (is it a rosbridge server?), ``state`` (watchdog), ``services`` (one
  blocking call), ``publish`` (commands, goals), ``side_channel`` (a second short-lived websocket).
* ``streams/``: what the chair sends. ``hub`` (odometry, scan, pose, tf; callbacks only store),
  ``messages`` + ``ranges`` (the typed records), ``throttle``, ``mapwatch``, ``tfwatch``, ``navlayers``,
  ``planpath``, ``fields`` + ``series`` (Plots), ``inspect`` (topic inspector).
* ``query/``: what the chair is asked. ``discovery`` (rosapi), ``reload`` (the map reload services),
  ``mapread`` (the published map), ``bridge_kind``, ``connectivity`` (the connection test).
* ``goals/``: navigation goals. ``navigate`` over ``goal``, ``goal_routes``, ``goal_topic``,
  ``goal_attach``, ``goal_watch``, ``goal_stop``, ``heartbeat``, ``goal_words``; ``initialpose``.
* ``record/``: topics to MCAP. ``recording``, ``record_convert``, ``msgdefs``, ``msgdetails``.

The rooms import downwards only: transport <- streams <- goals <- query <- record <- client (a helper's
``LinkCore`` annotation, imported for type checking only, aside).
"""

from __future__ import annotations

from pmk_nb.chair.link.client import ChairLink, ConnectionReport
from pmk_nb.chair.link.core import LinkCore
from pmk_nb.chair.link.goals import goal_words
from pmk_nb.chair.link.goals.goal_stop import GoalsStopped
from pmk_nb.chair.link.goals.navigate import GoalHandle, GoalProgress, GoalStatus
from pmk_nb.chair.link.linkconfig import LinkConfig
from pmk_nb.chair.link.record.recording import Recording, RecordStats
from pmk_nb.chair.link.registry import close_all_links, forget_link, get_link, open_links, use_only
from pmk_nb.chair.link.roles import GoalLink, LayerLink, MapWatchLink, PoseLink
from pmk_nb.chair.link.streams.fields import field_value, numeric_fields
from pmk_nb.chair.link.streams.inspect import TopicProbe, pretty_message, rate_text, topic_rows
from pmk_nb.chair.link.streams.navlayers import LAYERS, Costmap, Footprint, NavLayerWatch
from pmk_nb.chair.link.streams.planpath import AUTO, PlannedPath, PlanWatch
from pmk_nb.chair.link.streams.series import TopicSeries
from pmk_nb.chair.link.streams.tfwatch import TfWatch
from pmk_nb.chair.link.transport.state import LinkState
from pmk_nb.chair.link.transport.tls import trust_certificate

__all__ = [
    "AUTO",
    "LAYERS",
    "ChairLink",
    "ConnectionReport",
    "Costmap",
    "Footprint",
    "GoalHandle",
    "GoalLink",
    "GoalProgress",
    "GoalStatus",
    "GoalsStopped",
    "LayerLink",
    "LinkConfig",
    "LinkCore",
    "LinkState",
    "MapWatchLink",
    "NavLayerWatch",
    "PlanWatch",
    "PlannedPath",
    "PoseLink",
    "RecordStats",
    "Recording",
    "TfWatch",
    "TopicProbe",
    "TopicSeries",
    "close_all_links",
    "field_value",
    "forget_link",
    "get_link",
    "goal_words",
    "numeric_fields",
    "open_links",
    "pretty_message",
    "rate_text",
    "topic_rows",
    "trust_certificate",
    "use_only",
]
