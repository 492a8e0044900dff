"""The TF tree view's link side (issue 40): ``/tf`` and ``/tf_static`` on subscriptions of its own,
into a :class:`~pmk_nb.viewport.TfTree` stamped on a clock, only while the view is open.

The link's own tree hears ``/tf`` only when its pose comes from tf (``pose_source="tf"``), so the
view subscribes for itself, unthrottled (a throttle would make the rates lie) with a queue as the
link's /tf has (several publishers share the topic), and ends exactly its subscriptions on
:meth:`TfWatch.stop`. The I/O thread parses and stores; the rows are made on the page's timer.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from pmk_nb.chair.link.streams.hub import TF_QUEUE_LENGTH
from pmk_nb.chair.link.streams.inspect import OwnSubscription
from pmk_nb.chair.link.streams.messages import parse_tf_message
from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.viewport import TfTree
from pmk_nb.wire import spell_type

if TYPE_CHECKING:
    import roslibpy

__all__ = ["TfWatch"]

TF_TYPE = "tf2_msgs/TFMessage"


class TfWatch:
    """Every transform on ``/tf`` and ``/tf_static`` into ``tree`` (received at ``clock.now()``)."""

    def __init__(self, ros: roslibpy.Ros, ros_version: int | None, *, clock: Clock = MONOTONIC) -> None:
        self.clock = clock
        self.tree = TfTree()
        self.count = 0
        type_name = spell_type(TF_TYPE, ros_version)
        self._subs = [
            OwnSubscription(ros, "/tf", type_name, self._on_tf, 0, TF_QUEUE_LENGTH),
            OwnSubscription(ros, "/tf_static", type_name, self._on_tf_static, 0, TF_QUEUE_LENGTH),
        ]

    def _on_tf(self, msg: Any, static: bool = False) -> None:  # I/O thread: parse and store
        now = self.clock.now()
        for t in parse_tf_message(msg if isinstance(msg, dict) else {}):
            self.tree.set(t, now, static=static)
        self.count += 1

    def _on_tf_static(self, msg: Any) -> None:
        self._on_tf(msg, static=True)

    def stop(self) -> None:
        """End this watch's two subscriptions only (the link's own /tf stream goes on)."""
        for sub in self._subs:
            sub.stop()
