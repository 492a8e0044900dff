"""A picture of the witness's findings on the written map: where a leak or a blocked door is, at a glance.

Each finding is a numbered ring at its place (the number is its line in the report), coloured by
kind. Large maps are shrunk to :data:`MAX_SIDE` pixels (greys
averaged), so the picture stays a picture.
"""

from __future__ import annotations

import io
import os
from typing import TYPE_CHECKING

import numpy as np
from PIL import Image, ImageDraw

from pmk_nb.fileio import atomic_write
from pmk_nb.grid import GRAY_LUT
from pmk_nb.witness.findings import FindingKind

if TYPE_CHECKING:
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.witness.findings import Finding

MAX_SIDE = 2400
COLOURS = {
    FindingKind.LEAK: (220, 20, 60),
    FindingKind.BLOCKED: (255, 140, 0),
    FindingKind.NARROW: (255, 140, 0),
    FindingKind.NO_WAY_THROUGH: (255, 140, 0),
    FindingKind.ROOM_NOT_FREE: (160, 32, 240),
    FindingKind.OBSTACLE_FREE: (160, 32, 240),
    FindingKind.OUTSIDE_MAP: (30, 144, 255),
    FindingKind.OVERLAP: (30, 144, 255),
    FindingKind.IMPLAUSIBLE: (30, 144, 255),
}


def findings_png(grid: OccupancyGrid, findings: list[Finding]) -> bytes:
    """The map with each finding ringed and numbered, as PNG bytes (RGB: a picture for people)."""
    greys = GRAY_LUT[grid.data.view(np.uint8)][::-1]  # image row 0 is the top
    h, w = greys.shape
    scale = min(1.0, MAX_SIDE / max(h, w))
    image = Image.fromarray(np.ascontiguousarray(greys), mode="L")
    if scale < 1.0:
        image = image.resize((max(1, round(w * scale)), max(1, round(h * scale))), Image.Resampling.BOX)
    image = image.convert("RGB")
    draw = ImageDraw.Draw(image)
    ring = max(10, round(1.0 / grid.resolution * scale))  # a metre, at least 10 pixels
    for n, f in enumerate(findings, 1):
        col = (f.place[0] - grid.origin[0]) / grid.resolution * scale
        row = (h - (f.place[1] - grid.origin[1]) / grid.resolution) * scale
        colour = COLOURS[f.kind]
        for width in range(3):
            draw.ellipse(
                (col - ring - width, row - ring - width, col + ring + width, row + ring + width), outline=colour
            )
        draw.text((col + ring + 4, row - ring - 4), str(n), fill=colour)
    out = io.BytesIO()
    image.save(out, format="PNG")
    return out.getvalue()


def write_picture(path: str | os.PathLike[str], grid: OccupancyGrid, findings: list[Finding]) -> None:
    """Write :func:`findings_png` to ``path`` (atomically: an old picture stays whole until replaced)."""
    atomic_write(path, findings_png(grid, findings))
