"""Planar pose maths: (x, y, yaw) transforms, composed, inverted, applied; a sensor's pose on the chair.

A wheelchair moves in the plane, so (x, y, yaw) transforms are exact for it and far cheaper than a
full tf2 buffer. Pure: the tf tree (``tftree``, which the link fills from ``/tf``) and the canvas layers
both use it, so it lives with the live view's other maths rather than inside the link.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pmk_nb.wire import wrap_angle


@dataclass(frozen=True)
class Transform2D:
    """Pose of a child frame in its parent: p_parent = R(theta) p_child + (x, y)."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0

    def compose(self, other: Transform2D) -> Transform2D:
        """``self * other``: if self is parent<-mid and other is mid<-child, the result is parent<-child."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Transform2D(
            self.x + c * other.x - s * other.y,
            self.y + s * other.x + c * other.y,
            wrap_angle(self.theta + other.theta),
        )

    def inverse(self) -> Transform2D:
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Transform2D(-(c * self.x + s * self.y), s * self.x - c * self.y, wrap_angle(-self.theta))

    def apply(self, px: float, py: float) -> tuple[float, float]:
        """Map a point from the child frame into the parent frame."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return self.x + c * px - s * py, self.y + s * px + c * py


def mounted(pose: tuple[float, float, float], mount: tuple[float, float, float]) -> tuple[float, float, float]:
    """World pose of a sensor mounted at ``mount`` (base <- sensor) on a chair at ``pose`` (world <- base)."""
    tf = Transform2D(*pose).compose(Transform2D(*mount))
    return tf.x, tf.y, tf.theta
