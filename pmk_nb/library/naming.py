"""Names: of maps given by the user, and of generated map files (one rule for `pmk convert`, the
maps folder and its scan)."""

from __future__ import annotations

import os
import re

from pmk_nb.errors import LibraryError

SOURCE_SUFFIXES = (".gml", ".xml")
MAX_NAME_LENGTH = 100
_NAME_RE = re.compile(r"^[\w .-]+$")


def check_name(name: str) -> str:
    """Validate a map name given by the user; returns it without a ``.gml``/``.xml`` suffix.

    Raises:
        LibraryError: empty, too long, a path separator, a leading dot, or other characters than
            letters, digits, space, ``-``, ``_`` and ``.``.
    """
    if not isinstance(name, str) or not name.strip():
        raise LibraryError("a map name is required")
    if name.lower().endswith(SOURCE_SUFFIXES):
        name = name[:-4]
    problem = None
    if "/" in name or "\\" in name or os.sep in name:
        problem = "must not contain a path separator"
    elif name.startswith("."):
        problem = "must not start with a dot"
    elif name != name.strip():
        problem = "must not start or end with a space"
    elif len(name) > MAX_NAME_LENGTH:
        problem = f"is {len(name)} characters long; at most {MAX_NAME_LENGTH} are allowed"
    elif not _NAME_RE.match(name):
        bad = sorted({c for c in name if not _NAME_RE.match(c)})
        problem = f"contains {''.join(bad)!r}; use letters, digits, space, '-', '_' and '.'"
    if problem:
        raise LibraryError(f"invalid map name {name!r}: it {problem}")
    return name


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
