"""The rosbridge link to one chair (roslibpy): connection test, streams, discovery, map, services.

``client`` holds :class:`ChairLink`, the chair-level verbs, built from a :class:`LinkConfig`
(``linkconfig``) around a small public core (``core.LinkCore``: what the helpers use); underneath,
``transport`` and ``factory`` (roslibpy on a private asyncio loop), ``probe`` (is it a rosbridge
server?), ``connectivity`` (the connection test), ``streams`` (odometry, scan, pose, tf; callbacks
only store), ``publish`` (commands, goals), ``services`` (one blocking call), ``discovery``
(rosapi), ``mapread`` (the published map), ``state`` and ``registry`` (the kernel's only set of
links: one per chair); ``record`` (``ChairLink.record`` / ``start_recording``: topics to an MCAP
file with ROS 2 schemas); ``navlayers`` (Nav2's costmaps, footprint, local plan and markers, found by
type); ``fields`` + ``series`` (any numeric field of any topic, sampled for the Plots); ``tfwatch``
(``/tf`` and ``/tf_static`` for the TF tree view);
``goal_stop`` (``ChairLink.stop_goals``: the Stop for navigation goals, and the goal gate a latched
Stop closes).
"""

from __future__ import annotations

from pmk_nb.chair.link.client import ChairLink, ConnectionReport
from pmk_nb.chair.link.fields import field_value, numeric_fields
from pmk_nb.chair.link.fleet_links import FleetLinks
from pmk_nb.chair.link.goal_stop import GoalsStopped
from pmk_nb.chair.link.inspect import TopicProbe, pretty_message, rate_text, topic_rows
from pmk_nb.chair.link.linkconfig import LinkConfig
from pmk_nb.chair.link.navigate import GoalHandle, GoalProgress, GoalStatus
from pmk_nb.chair.link.navlayers import LAYERS, Costmap, Footprint, NavLayerWatch
from pmk_nb.chair.link.planpath import AUTO, PlannedPath, PlanWatch
from pmk_nb.chair.link.record import Recording, RecordStats
from pmk_nb.chair.link.registry import close_all_links, forget_link, get_link, open_links, use_only
from pmk_nb.chair.link.series import TopicSeries
from pmk_nb.chair.link.state import LinkState
from pmk_nb.chair.link.tfwatch import TfWatch
from pmk_nb.chair.link.tls import trust_certificate

__all__ = [
    "AUTO",
    "LAYERS",
    "ChairLink",
    "ConnectionReport",
    "Costmap",
    "FleetLinks",
    "Footprint",
    "GoalHandle",
    "GoalProgress",
    "GoalStatus",
    "GoalsStopped",
    "LinkConfig",
    "LinkState",
    "NavLayerWatch",
    "PlanWatch",
    "PlannedPath",
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
