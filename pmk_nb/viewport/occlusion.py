"""Which part of the live canvas panels cover, and where the view's focus goes so the chair stays clear.

Panels float over the map (the Drive panel's joystick and Stop at the rider's side, the tool bar at
the top, the status line at the bottom).  Each covers a strip along one edge of the canvas; the
rest is the *uncovered part*, and following puts the chair in its centre rather than in the
canvas's centre (:meth:`pmk_nb.viewport.Viewport.set_insets`).  Pure maths on canvas pixels, no
widgets: the page reports the panels' boxes, :func:`insets_from_boxes` turns them into
:class:`Insets`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

#: The uncovered part never shrinks below this share of the canvas along an axis: panels that
#: would cover more are taken as covering less (the chair must still fit somewhere on screen).
MIN_UNCOVERED_SHARE = 0.25

Box = tuple[float, float, float, float]  # x, y, width, height in canvas pixels


@dataclass(frozen=True)
class Insets:
    """How far panels reach in from each edge of the canvas, in canvas pixels (all >= 0)."""

    left: float = 0.0
    top: float = 0.0
    right: float = 0.0
    bottom: float = 0.0

    def fitted(self, width: float, height: float) -> Insets:
        """These insets on a ``width`` x ``height`` canvas: non-finite or negative -> 0, and each
        axis scaled down so that :data:`MIN_UNCOVERED_SHARE` of it stays uncovered."""
        left, top, right, bottom = (_clean(v) for v in (self.left, self.top, self.right, self.bottom))
        left, right = _fit_pair(left, right, max(float(width), 0.0))
        top, bottom = _fit_pair(top, bottom, max(float(height), 0.0))
        return Insets(left, top, right, bottom)

    def focus_offset(self) -> tuple[float, float]:
        """Where the centre of the uncovered part is, in pixels from the canvas's centre (x right, y down)."""
        return (self.left - self.right) / 2.0, (self.top - self.bottom) / 2.0

    def uncovered(self, width: float, height: float) -> Box:
        """The uncovered part of a ``width`` x ``height`` canvas as (x, y, width, height)."""
        fit = self.fitted(width, height)
        return fit.left, fit.top, width - fit.left - fit.right, height - fit.top - fit.bottom


def _clean(value: float) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        return 0.0
    return v if math.isfinite(v) and v > 0 else 0.0


def _fit_pair(low: float, high: float, size: float) -> tuple[float, float]:
    most = size * (1.0 - MIN_UNCOVERED_SHARE)
    total = low + high
    if total <= most or total <= 0:
        return low, high
    k = most / total
    return low * k, high * k


def insets_from_boxes(width: float, height: float, boxes: Iterable[Box]) -> Insets:
    """The insets that uncover every box: each box (clipped to the canvas) gives up the strip along
    the edge that costs least (a panel at the right edge gives a right inset of its width, a bar
    across the top a top inset of its height); boxes outside the canvas or not finite are ignored."""
    left = top = right = bottom = 0.0
    for box in boxes:
        try:
            x, y, bw, bh = (float(v) for v in box)
        except (TypeError, ValueError):
            continue
        if not all(math.isfinite(v) for v in (x, y, bw, bh)) or bw <= 0 or bh <= 0:
            continue
        x0, y0 = max(x, 0.0), max(y, 0.0)
        x1, y1 = min(x + bw, float(width)), min(y + bh, float(height))
        if x1 <= x0 or y1 <= y0:
            continue
        strips = {"left": x1, "right": width - x0, "top": y1, "bottom": height - y0}
        side = min(strips, key=lambda k: strips[k])
        if side == "left":
            left = max(left, strips[side])
        elif side == "right":
            right = max(right, strips[side])
        elif side == "top":
            top = max(top, strips[side])
        else:
            bottom = max(bottom, strips[side])
    return Insets(left, top, right, bottom).fitted(width, height)
