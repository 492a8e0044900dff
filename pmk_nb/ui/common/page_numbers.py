"""Numbers a page sends (canvas events, measurements): untrusted, so checked in one place.

Any page can send any JSON: ``float()`` raises OverflowError on a 400-digit integer (issue 38), and
a finite 1e300 still turns into inf once two are subtracted or squared. So a page number is taken
only when it is a real number (no bool) that ``float()`` accepts and lies within ``limit``.
"""

from __future__ import annotations

import math

#: Pixels: far beyond any screen, small enough that sums, differences and squares stay finite.
PAGE_PX_LIMIT = 1e6


def page_number(value: object, limit: float = PAGE_PX_LIMIT) -> float | None:
    """``value`` as a float when it is a number ``float()`` takes with ``|value| <= limit``, else None."""
    if isinstance(value, bool):
        return None
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return None
    return number if math.isfinite(number) and abs(number) <= limit else None
