"""File names of generated maps: one rule for `pmk convert`, the maps folder and its scan."""

from __future__ import annotations

import re


def safe_file_part(text: str) -> str:
    """``text`` reduced to characters safe in a file name on every OS (others become ``_``)."""
    cleaned = re.sub(r"[^A-Za-z0-9._-]+", "_", text.strip()).strip("._")
    return cleaned or "storey"


def storey_map_names(base: str, storeys: list[str], *, several: bool | None = None) -> dict[str, str]:
    """Map set names per storey: ``base`` for a single storey, ``base_<storey>`` when there are several.

    Storey names are sanitised for file names; names that collide after that get ``-2``, ``-3``...
    """
    if several is None:
        several = len(storeys) > 1
    if not several:
        return {s: base for s in storeys}
    out: dict[str, str] = {}
    used: set[str] = set()
    for storey in storeys:
        name = f"{base}_{safe_file_part(storey)}"
        candidate, n = name, 1
        while candidate.lower() in used:
            n += 1
            candidate = f"{name}-{n}"
        used.add(candidate.lower())
        out[storey] = candidate
    return out
