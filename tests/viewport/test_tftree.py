"""The tf tree the link fills from /tf (moved from chair/link to viewport, issue 25): chains composed both
ways, the oldest dynamic receive time kept, cycles survived."""

from __future__ import annotations

import math
from dataclasses import dataclass

import pytest

from pmk_nb.viewport import TfTree


@dataclass(frozen=True)
class _T:
    """A planar transform as the link hands it over (``chair.link.streams.messages.TransformStamped2D``'s shape)."""

    parent: str
    child: str
    x: float
    y: float
    theta: float


def test_tf_tree_composes_map_odom_base_link() -> None:
    tree = TfTree()
    tree.set(_T("odom", "base_link", 1.0, 0.0, math.pi / 2), received=10.0)
    tree.set(_T("map", "odom", 2.0, 3.0, math.pi / 2), received=8.0)
    tree.set(_T("base_link", "laser", 0.2, 0.0, 0.0), received=0.0, static=True)
    found = tree.lookup("/map", "base_link")  # ROS 1 spelling: the same frame
    assert found is not None
    tf, oldest = found
    # odom->base_link (1,0) rotated by map->odom's 90 deg -> (0,1), plus (2,3)
    assert (tf.x, tf.y) == pytest.approx((2.0, 4.0))
    assert tf.theta == pytest.approx(math.pi)
    assert oldest == 8.0  # the oldest dynamic link of the chain
    laser_in_odom, _ = tree.lookup("odom", "laser")  # type: ignore[misc]
    assert (laser_in_odom.x, laser_in_odom.y) == pytest.approx((1.0, 0.2))
    # the reverse direction is the inverse
    back, _ = tree.lookup("base_link", "map")  # type: ignore[misc]
    again = back.compose(tf)
    assert (again.x, again.y) == pytest.approx((0.0, 0.0), abs=1e-9)
    assert tree.lookup("map", "nowhere") is None


def test_tf_tree_ignores_cycles() -> None:
    tree = TfTree()
    for parent, child in (("a", "b"), ("b", "a")):
        tree.set(_T(parent, child, 1.0, 0.0, 0.0), received=1.0)
    assert tree.lookup("map", "a") is None  # terminates despite the loop
