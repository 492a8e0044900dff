"""WCAG 2.2 colour contrast maths: relative luminance and contrast ratio of two sRGB colours.

The style sheet's colour pairs (text on its background, focus ring on what surrounds it) are
checked with these in the unit tests, so a colour changed in :mod:`pmk_nb.ui.common.a11y_style` that
falls under the AA minimum fails before a page is ever opened.  Formulas: WCAG 2.2, "relative
luminance" and "contrast ratio" definitions (sRGB, linearised with the 0.04045 threshold).
"""

from __future__ import annotations

import re

#: WCAG 2.2 AA minimums: normal text (1.4.3), large text (1.4.3) and non-text parts such as a
#: focus indicator or a control's border (1.4.11).
TEXT_AA = 4.5
LARGE_TEXT_AA = 3.0
NON_TEXT_AA = 3.0

_HEX = re.compile(r"^#([0-9a-fA-F]{3}|[0-9a-fA-F]{6})$")


def parse_hex(colour: str) -> tuple[int, int, int]:
    """``#rgb`` or ``#rrggbb`` -> (r, g, b) in 0..255; anything else is a ValueError."""
    match = _HEX.match(colour.strip())
    if match is None:
        raise ValueError(f"not a #rgb or #rrggbb colour: {colour!r}")
    digits = match.group(1)
    if len(digits) == 3:
        digits = "".join(c * 2 for c in digits)
    r, g, b = (int(digits[i : i + 2], 16) for i in (0, 2, 4))
    return r, g, b


def relative_luminance(colour: str) -> float:
    """WCAG relative luminance of an sRGB colour: 0 (black) to 1 (white)."""

    def linear(channel: int) -> float:
        c = channel / 255.0
        return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4

    r, g, b = (linear(c) for c in parse_hex(colour))
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def contrast_ratio(first: str, second: str) -> float:
    """(L1 + 0.05) / (L2 + 0.05) with L1 the lighter one: 1 (same) to 21 (black on white)."""
    a, b = relative_luminance(first), relative_luminance(second)
    lighter, darker = max(a, b), min(a, b)
    return (lighter + 0.05) / (darker + 0.05)
