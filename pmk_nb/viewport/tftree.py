"""A tiny tf tree, enough to compose map -> odom -> base_link (the planar maths: ``pose``).

A wheelchair moves in the plane, so (x, y, yaw) transforms are exact for it and far cheaper than
a full tf2 buffer. The tree keeps only the latest transform per child frame (no interpolation):
the live view wants "where is the chair now", not a pose at a past instant. Pure (issue 25): the
link (``pmk_nb.chair.link.streams.hub``) fills it from ``/tf`` with the transforms ``chair.link.streams.messages``
parses; the maths lives here, with the live view's other maths, and knows no ROS message.
"""

from __future__ import annotations

import builtins
import math
import threading
from collections import deque
from dataclasses import dataclass
from typing import Protocol

from pmk_nb.viewport.pose import Transform2D


def normalise_frame(frame: str) -> str:
    """tf frame ids without the leading '/' ROS 1 tf allowed (``/odom`` == ``odom``)."""
    return frame.lstrip("/")


class FramedTransform(Protocol):
    """One planar transform: ``child`` expressed in ``parent`` (``chair.link.streams.messages.TransformStamped2D``)."""

    @property
    def parent(self) -> str: ...
    @property
    def child(self) -> str: ...
    @property
    def x(self) -> float: ...
    @property
    def y(self) -> float: ...
    @property
    def theta(self) -> float: ...


@dataclass(frozen=True)
class _Edge:
    parent: str
    tf: Transform2D
    received: float
    static: bool


@dataclass(frozen=True)
class EdgeRecord:
    """What the tree knows of one child frame: its parent, whether from ``/tf_static``, when its
    recent transforms arrived (the times ``set`` was given, oldest first)."""

    parent: str
    static: bool
    arrivals: tuple[float, ...]


class TfTree:
    """Latest planar transform per child frame, from ``/tf`` and ``/tf_static``.

    Written by the I/O thread, read by any thread: one short lock around a dict, never held
    while doing anything slow.
    """

    MAX_DEPTH = 32  # guards against cycles from misconfigured publishers
    ARRIVALS = 64  # receive times kept per child frame: its rate for the TF tree view (``tfframes``)

    def __init__(self) -> None:
        self._edges: dict[str, _Edge] = {}
        self._arrivals: dict[str, deque[float]] = {}
        self._lock = threading.Lock()

    def set(self, t: FramedTransform, received: float, *, static: bool = False) -> None:
        if not t.child or not t.parent or t.child == t.parent:
            return
        edge = _Edge(t.parent, Transform2D(t.x, t.y, t.theta), received, static)
        with self._lock:
            self._edges[t.child] = edge
            arrivals = self._arrivals.get(t.child)
            if arrivals is None:
                arrivals = self._arrivals[t.child] = deque(maxlen=self.ARRIVALS)
            arrivals.append(received)

    def clear(self) -> None:
        with self._lock:
            self._edges.clear()
            self._arrivals.clear()

    def edges(self) -> dict[str, EdgeRecord]:
        """Every child frame's parent, static flag and recent receive times (oldest first): a copy."""
        with self._lock:
            return {
                child: EdgeRecord(e.parent, e.static, tuple(self._arrivals.get(child, ())))
                for child, e in self._edges.items()
            }

    def frames(self) -> builtins.set[str]:  # builtins: ``set`` is the method above here
        with self._lock:
            return set(self._edges) | {e.parent for e in self._edges.values()}

    def _chain_to_root(self, frame: str, edges: dict[str, _Edge]) -> list[tuple[str, Transform2D, float]]:
        """[(frame, root<-frame, oldest received on the way)] walking up the parents."""
        chain = [(frame, Transform2D(), math.inf)]
        tf, oldest, cur = Transform2D(), math.inf, frame
        for _ in range(self.MAX_DEPTH):
            edge = edges.get(cur)
            if edge is None:
                break
            tf = edge.tf.compose(tf)  # parent<-cur * cur<-frame
            if not edge.static:
                oldest = min(oldest, edge.received)
            cur = edge.parent
            chain.append((cur, tf, oldest))
        return chain

    def lookup(self, target: str, source: str) -> tuple[Transform2D, float] | None:
        """(target<-source, oldest non-static receive time) or None when the frames are not connected.

        The receive time is ``inf`` when the whole chain is static.
        """
        target, source = normalise_frame(target), normalise_frame(source)
        with self._lock:
            edges = dict(self._edges)
        up_source = self._chain_to_root(source, edges)
        up_target = {f: (tf, rec) for f, tf, rec in self._chain_to_root(target, edges)}
        for frame, root_from_source, rec_s in up_source:
            if frame in up_target:
                common_from_target, rec_t = up_target[frame]
                return common_from_target.inverse().compose(root_from_source), min(rec_s, rec_t)
        return None
