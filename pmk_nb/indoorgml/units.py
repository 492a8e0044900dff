"""Choosing the length unit of a file that does not say (no IndoorGML file in the wild does).

Documented heuristic for ``unit="auto"``, first match wins:

1. ALMA style (MultiLayeredGraph with CellSpaces inline, indoorCore/indoorNavi or alma
   namespaces, map-frame translation/rotation): centimetres - the ALMA servers wrote 1 unit = 1 cm
   (thesis ch. 3.2).
2. Doors: when the file has doors (door boundaries or door cells), pick the unit that makes the
   median door width closest to 1 m, if that lands in 0.5-3 m. A wheelchair map is useless when
   doors are 0.15 m or 15 m wide, so this beats the overall size. (PNU 313: doors 5-21 units ->
   decimetres; PNU 201 and PNU abc: doors 1.3-3 units -> metres.)
3. Extent of the plan (largest side of the bounding box of all cells, storeys stack in plan):
   <= 250 units -> metres (UTM-sized coordinates have a small extent too); <= 1000 -> decimetres
   (no storey is 250 m to 1 km across); <= 100 000 -> centimetres; larger -> millimetres.
"""

from __future__ import annotations

import math

UNIT_SCALE: dict[str, float] = {"m": 1.0, "dm": 0.1, "cm": 0.01, "mm": 0.001}
UNIT_CHOICES = ("auto", *UNIT_SCALE)
DOOR_RANGE = (0.5, 3.0)


def choose_unit(*, alma: bool, alma_why: str, door_widths: list[float], extent: float) -> tuple[str, str]:
    """Return ``(unit, reason)`` for a file whose unit is not given; see the module docstring."""
    if alma:
        return "cm", f"auto: ALMA style ({alma_why}) -> centimetres"
    if door_widths:
        w = sorted(door_widths)[len(door_widths) // 2]
        best = min(UNIT_SCALE, key=lambda u: abs(math.log(max(w * UNIT_SCALE[u], 1e-12))))
        metres = w * UNIT_SCALE[best]
        if DOOR_RANGE[0] <= metres <= DOOR_RANGE[1]:
            return best, (
                f"auto: median door width {w:.3g} units -> {metres:.2f} m in {best} ({len(door_widths)} doors)"
            )
    for limit, unit in ((250.0, "m"), (1000.0, "dm"), (100_000.0, "cm")):
        if extent <= limit:
            return unit, (
                f"auto: plan extent {extent:.4g} units <= {limit:g} -> {unit} "
                f"({extent * UNIT_SCALE[unit]:.1f} m across)"
            )
    return "mm", f"auto: plan extent {extent:.4g} units > 100000 -> mm ({extent / 1000:.1f} m across)"
