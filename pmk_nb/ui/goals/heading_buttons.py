"""A drag-free heading: eight compass buttons (and Automatic) for where the chair should face.

Setting a destination's heading by dragging needs a steady finger; a rider with limited reach or a
tremor taps one of these instead, then taps the map (issue 28).  The directions are the screen's
(up = the top of the map), which is the map frame's +y: the live view never rotates the map.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import ipywidgets as w

from pmk_nb.ui.common.widgets import TOUCH_PX

AUTO = "auto"
#: (label, tooltip, heading in degrees in the map frame: 0 = right, 90 = up)
DIRECTIONS: tuple[tuple[str, str, float], ...] = (
    ("↖", "Face up and left", 135.0),
    ("↑", "Face up", 90.0),
    ("↗", "Face up and right", 45.0),
    ("←", "Face left", 180.0),
    ("→", "Face right", 0.0),
    ("↙", "Face down and left", 225.0),
    ("↓", "Face down", 270.0),
    ("↘", "Face down and right", 315.0),
)


def heading_of(value: object) -> float | None:
    """The heading (radians) for a chosen value; None for Automatic or anything unknown."""
    for label, _tip, degrees in DIRECTIONS:
        if value == label:
            return math.radians(degrees)
    return None


class HeadingButtons:
    """``widget``: Automatic plus eight arrows; ``on_change(heading or None)`` on every choice."""

    def __init__(self, on_change: Callable[[float | None], None]) -> None:
        self.on_change = on_change
        options = [("Auto", AUTO), *[(label, label) for label, _t, _d in DIRECTIONS]]
        tooltips = ["Face away from the chair", *[tip for _l, tip, _d in DIRECTIONS]]
        self.choice = w.ToggleButtons(options=options, value=AUTO, tooltips=tooltips, style={"button_width": "auto"})
        self.choice.add_class("pmk-heading-buttons")
        self.choice.observe(self._on_choice, names="value")
        self.label = w.HTML("Face when there:")
        self.label.add_class("pmk-heading-label")
        self.widget = w.VBox([self.label, self.choice])
        self.widget.add_class("pmk-heading")
        self.widget.layout.min_height = f"{TOUCH_PX}px"

    @property
    def heading(self) -> float | None:
        return heading_of(self.choice.value)

    def reset(self) -> None:
        self.choice.value = AUTO

    def _on_choice(self, _change: dict[str, object]) -> None:
        self.on_change(self.heading)
