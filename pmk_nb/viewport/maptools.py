"""The map tools' pure maths: scale bar, grid lines, distances and headings in the map frame.

No widgets: :mod:`pmk_nb.ui.live.tools` draws what these return. A scale bar is a round length
(1, 2 or 5 x 10^k m) no longer than the room it is given on screen, so it reads at a glance at any
zoom; grid lines are the multiples of a spacing that fall inside the view (a fixed 1 m, or "auto":
the scale bar's rule applied to a target pixel gap, so lines never crowd nor vanish).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pmk_nb.viewport.view import Viewport

NICE_STEPS = (1.0, 2.0, 5.0)
MAX_GRID_LINES = 200  # per axis: more would be a grey wash, and a page flood


@dataclass(frozen=True)
class ScaleBar:
    """A bar ``metres`` long that is ``pixels`` long on screen; ``label`` is what it says."""

    metres: float
    pixels: float
    label: str


def nice_length(at_most: float) -> float:
    """The largest 1, 2 or 5 x 10^k no larger than ``at_most`` (> 0 and finite, else ValueError)."""
    if not (math.isfinite(at_most) and at_most > 0):
        raise ValueError(f"a length must be finite and > 0, got {at_most}")
    exponent = math.floor(math.log10(at_most))
    for step in reversed(NICE_STEPS):
        value = step * 10.0**exponent
        if value <= at_most * (1 + 1e-9):
            return float(f"{value:.12g}")
    return float(f"{5.0 * 10.0 ** (exponent - 1):.12g}")


def length_label(metres: float) -> str:
    """Metres in words a person reads: "50 cm", "2 m", "1.5 km", "0.25 m" for odd values."""
    if metres >= 1000:
        return f"{metres / 1000:g} km"
    if metres >= 1:
        return f"{metres:g} m"
    if metres >= 0.01 and abs(metres * 100 - round(metres * 100)) < 1e-6:
        return f"{round(metres * 100)} cm"
    return f"{metres:.3g} m"


def scale_bar(px_per_m: float, max_px: float) -> ScaleBar:
    """The longest round length whose bar fits in ``max_px`` pixels at ``px_per_m`` (the view's)."""
    if not (math.isfinite(px_per_m) and px_per_m > 0):
        raise ValueError(f"pixels per metre must be finite and > 0, got {px_per_m}")
    metres = nice_length(max_px / px_per_m)
    return ScaleBar(metres, metres * px_per_m, length_label(metres))


def grid_spacing(px_per_m: float, spacing: float | None = 1.0, min_gap_px: float = 40.0) -> float:
    """Metres between grid lines: ``spacing`` if given, else ("auto") the round length nearest above
    ``min_gap_px`` on screen."""
    if spacing is not None:
        if not (math.isfinite(spacing) and spacing > 0):
            raise ValueError(f"grid spacing must be finite and > 0 m, got {spacing}")
        return float(spacing)
    if not (math.isfinite(px_per_m) and px_per_m > 0):
        raise ValueError(f"pixels per metre must be finite and > 0, got {px_per_m}")
    at_least = min_gap_px / px_per_m
    exponent = math.floor(math.log10(at_least))
    for e in (exponent, exponent + 1):
        for step in NICE_STEPS:
            value = step * 10.0**e
            if value >= at_least * (1 - 1e-9):
                return float(f"{value:.12g}")
    return float(f"{10.0 ** (exponent + 1):.12g}")  # unreachable: 10^(e+1) >= at_least


def grid_lines(view: Viewport, spacing: float) -> tuple[list[tuple[float, float]], list[tuple[float, float]]]:
    """The grid lines in view: ([(world x, pixel x)] of vertical lines, [(world y, pixel y)] of
    horizontal ones), at the multiples of ``spacing`` metres (x = 0 and y = 0 are lines); none when
    more than :data:`MAX_GRID_LINES` would show on an axis."""
    if not (math.isfinite(spacing) and spacing > 0):
        raise ValueError(f"grid spacing must be finite and > 0 m, got {spacing}")
    (x0, x1), (y_top, y_bottom) = view.pixel_to_world([0.0, float(view.canvas_width)], [0.0, float(view.canvas_height)])
    out: list[list[tuple[float, float]]] = []
    for lo, hi, axis in ((float(x0), float(x1), 0), (float(y_bottom), float(y_top), 1)):
        lo, hi = min(lo, hi), max(lo, hi)
        first, last = math.ceil(lo / spacing - 1e-9), math.floor(hi / spacing + 1e-9)
        if last - first + 1 > MAX_GRID_LINES:
            out.append([])
            continue
        lines = []
        for k in range(first, last + 1):
            metres = k * spacing
            px = view.world_to_pixel(metres, 0.0)[0] if axis == 0 else view.world_to_pixel(0.0, metres)[1]
            lines.append((float(f"{metres:.12g}"), float(px)))
        out.append(lines)
    return out[0], out[1]


def pixel_to_map(view: Viewport, px: float, py: float) -> tuple[float, float] | None:
    """Where a canvas pixel is in the map frame (metres); None for a non-finite point."""
    if not (math.isfinite(px) and math.isfinite(py)):
        return None
    x, y = view.pixel_to_world(px, py)
    return float(x), float(y)


def distance(a: tuple[float, float], b: tuple[float, float]) -> float:
    """Straight-line metres between two map points."""
    return math.hypot(b[0] - a[0], b[1] - a[1])


def heading(a: tuple[float, float], b: tuple[float, float]) -> float:
    """Yaw (radians, map frame, counter-clockwise from +x) of the direction from ``a`` to ``b``."""
    return math.atan2(b[1] - a[1], b[0] - a[0])


def coordinates_text(point: tuple[float, float] | None) -> str:
    """A point as the page shows it: "x 1.25 m, y -3.40 m" (empty for None)."""
    if point is None:
        return ""
    return f"x {point[0]:.2f} m, y {point[1]:.2f} m"
