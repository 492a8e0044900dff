"""The rooms a rider goes to most: recent and favourite rooms per map, first in the Go to picker.

Kept in the settings folder (``room_picks.json``, written through :func:`pmk_nb.fileio.atomic_write`,
read through the one JSON-object reader) so that they survive a reload and are shared by every page
on this tablet; keyed by map name, as room names belong to a storey.  Bounded: at most
:data:`MAX_RECENT` recent rooms and :data:`MAX_FAVOURITES` favourites per map, :data:`MAX_MAPS` maps.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from pmk_nb.catalogue import read_json_object
from pmk_nb.fileio import atomic_write

PICKS_FILE = "room_picks.json"
MAX_RECENT = 5
MAX_FAVOURITES = 12
MAX_MAPS = 50


def _names(raw: object, most: int) -> list[str]:
    if not isinstance(raw, list):
        return []
    out: list[str] = []
    for item in raw:
        if isinstance(item, str) and item and item not in out:
            out.append(item)
    return out[:most]


class RoomPicks:
    """Recent and favourite rooms of each map, in ``config_dir / PICKS_FILE``."""

    def __init__(self, config_dir: Path) -> None:
        self.path = Path(config_dir) / PICKS_FILE

    def _maps(self) -> dict[str, Any]:
        maps = read_json_object(self.path).get("maps")
        return maps if isinstance(maps, dict) else {}

    def _entry(self, map_name: str) -> dict[str, list[str]]:
        raw = self._maps().get(map_name)
        raw = raw if isinstance(raw, dict) else {}
        return {
            "recent": _names(raw.get("recent"), MAX_RECENT),
            "favourites": _names(raw.get("favourites"), MAX_FAVOURITES),
        }

    def recent(self, map_name: str) -> list[str]:
        """The last rooms gone to on ``map_name``, newest first."""
        return self._entry(map_name)["recent"]

    def favourites(self, map_name: str) -> list[str]:
        return self._entry(map_name)["favourites"]

    def remember(self, map_name: str, room: str) -> None:
        """``room`` was just gone to: it heads the recent list."""
        entry = self._entry(map_name)
        entry["recent"] = [room, *[r for r in entry["recent"] if r != room]][:MAX_RECENT]
        self._save(map_name, entry)

    def toggle_favourite(self, map_name: str, room: str) -> bool:
        """Make ``room`` a favourite or not; returns whether it is one now."""
        entry = self._entry(map_name)
        favs = entry["favourites"]
        now = room not in favs
        entry["favourites"] = ([*favs, room] if now else [r for r in favs if r != room])[:MAX_FAVOURITES]
        self._save(map_name, entry)
        return now and room in entry["favourites"]

    def order(self, map_name: str, rooms: Sequence[str]) -> list[str]:
        """``rooms`` with the favourites first, then the recent ones, then the rest (as given)."""
        entry = self._entry(map_name)
        known = set(rooms)
        first = [r for r in [*entry["favourites"], *entry["recent"]] if r in known]
        head = list(dict.fromkeys(first))
        return head + [r for r in rooms if r not in head]

    def _save(self, map_name: str, entry: dict[str, list[str]]) -> None:
        maps = self._maps()
        maps.pop(map_name, None)
        maps[map_name] = entry  # the map used last goes last: the oldest are dropped first
        keep = dict(list(maps.items())[-MAX_MAPS:])
        atomic_write(self.path, json.dumps({"maps": keep}, indent=1), mkdir=True)
