"""Speed limits of one chair and the stick -> velocity mapping.

The stick is a unit disc: ``y`` forward (+1 full speed ahead), ``x`` to the right. A small dead
zone around the centre sends exactly zero (a resting thumb must not creep the chair), and the rest
of the travel is rescaled so that the edge of the dead zone starts from zero speed, not a jump.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

DEFAULT_MAX_LINEAR = 0.5  # m/s
DEFAULT_MAX_ANGULAR = 0.8  # rad/s
DEFAULT_SLOW_FACTOR = 0.4
DEFAULT_DEAD_ZONE = 0.12  # of the stick's radius


@dataclass(frozen=True)
class SpeedLimits:
    """Largest speeds the dashboard ever commands; ``slow_factor`` scales both in slow mode."""

    max_linear: float = DEFAULT_MAX_LINEAR
    max_angular: float = DEFAULT_MAX_ANGULAR
    slow_factor: float = DEFAULT_SLOW_FACTOR
    dead_zone: float = DEFAULT_DEAD_ZONE

    def __post_init__(self) -> None:
        for name in ("max_linear", "max_angular", "slow_factor"):
            value = getattr(self, name)
            if not math.isfinite(value) or value <= 0:
                raise ValueError(f"{name} must be a positive number, got {value!r}")
        if self.slow_factor > 1:
            raise ValueError(f"slow_factor must be at most 1, got {self.slow_factor!r}")
        if not 0 <= self.dead_zone < 1:
            raise ValueError(f"dead_zone must be in [0, 1), got {self.dead_zone!r}")

    def scale(self, slow: bool) -> tuple[float, float]:
        """(largest linear, largest angular) speed now."""
        k = self.slow_factor if slow else 1.0
        return self.max_linear * k, self.max_angular * k

    def clamp(self, v: float, w: float, slow: bool = False) -> tuple[float, float]:
        """A twist within the limits (a script asking for more gets the limit)."""
        vmax, wmax = self.scale(slow)
        v = float(v) if math.isfinite(v) else 0.0
        w = float(w) if math.isfinite(w) else 0.0
        return max(-vmax, min(vmax, v)), max(-wmax, min(wmax, w))


def stick_to_twist(x: float, y: float, limits: SpeedLimits, slow: bool = False) -> tuple[float, float]:
    """Stick position -> (v m/s, w rad/s); right on the stick turns right (negative w, REP 103)."""
    if not (math.isfinite(x) and math.isfinite(y)):
        return 0.0, 0.0
    r = math.hypot(x, y)
    if r <= limits.dead_zone:
        return 0.0, 0.0
    scale = (min(r, 1.0) - limits.dead_zone) / (1.0 - limits.dead_zone) / r
    vmax, wmax = limits.scale(slow)
    v, w = y * scale * vmax, -x * scale * wmax
    return (v if abs(v) > 1e-9 else 0.0), (w if abs(w) > 1e-9 else 0.0)
