"""Entry point: ``read_building(path)`` streams, validates and interprets one IndoorGML file."""

from __future__ import annotations

import hashlib
import os
from collections.abc import Sequence
from pathlib import Path

from pmk_nb.errors import IndoorGMLError
from pmk_nb.indoorgml.build import build_building
from pmk_nb.indoorgml.crs import CRS_AUTO, check_crs_option
from pmk_nb.indoorgml.model import Building
from pmk_nb.indoorgml.scan import scan
from pmk_nb.indoorgml.units import UNIT_CHOICES
from pmk_nb.progress import ProgressCallback


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            digest.update(chunk)
    return digest.hexdigest()


def read_building(
    path: str | os.PathLike[str],
    *,
    unit: str = "auto",
    progress: ProgressCallback | None = None,
    not_windows: Sequence[str] = (),
    layers: Sequence[str] = (),
    crs: str = CRS_AUTO,
) -> Building:
    """Read an IndoorGML file (1.0, 1.0.x, 1.1, 2.0 drafts, ALMA style) into a :class:`Building`.

    Args:
        path: the .gml file.
        unit: "m", "dm", "cm", "mm", or "auto" (see :mod:`pmk_nb.indoorgml.units`).
        progress: ``read`` reports (fraction of the file's bytes) while the file streams in.
        not_windows: ids or names of cells the window/sill rule must leave navigable (a door it
            misjudged; ``pmk check`` names the cells it took for windows).
        layers: ids or names of the space layers to draw, instead of the navigable one the reader
            picks (``Building.skipped_layers`` names each layer not drawn and why).
        crs: the frame of the coordinates: "auto" (the file's srsName, else judged), "local", or a CRS
            name such as "EPSG:3857" that replaces the file's (see :mod:`pmk_nb.indoorgml.crs`).

    Returns:
        The building, all coordinates in metres.

    Raises:
        IndoorGMLError: the file is missing, unsafe (DOCTYPE with entities), malformed, not
            IndoorGML, or holds no usable cell; the message names the file (and line/cell).
            :class:`~pmk_nb.errors.UnknownLayer` when ``layers`` names no layer with cells;
            :class:`~pmk_nb.indoorgml.crs.CrsError` for coordinates in degrees, a plan larger than any
            building, or an unknown ``crs``.
    """
    p = Path(path)
    if unit not in UNIT_CHOICES:
        raise IndoorGMLError(f"{p}: unknown unit {unit!r}; use one of {', '.join(UNIT_CHOICES)}", path=str(p))
    crs = check_crs_option(crs, str(p))
    if not p.is_file():
        raise IndoorGMLError(f"{p}: no such file", path=str(p))
    doc = scan(p, progress)
    return build_building(doc, _sha256(p), unit, not_windows, layers, crs)
