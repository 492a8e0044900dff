"""The choices a conversion needs from the user when the plan cannot say: its unit, and which cells the
window/sill rule took for windows that are really doors, and the space layers to draw when the user
asks for another than the navigable one.

The Maps screen offers both (the command line has ``--unit`` and ``--not-window``). What was chosen is
kept in each written storey's rooms file, under ``choices``, so that converting again (a finer
resolution, another chair) keeps them without the user having to remember.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, TypeGuard

from pmk_nb.indoorgml import UNIT_CHOICES
from pmk_nb.openings import SKIP_WINDOW

CHOICES_KEY = "choices"  # where a rooms file keeps them


@dataclass(frozen=True)
class ConvertChoices:
    unit: str = "auto"  # "auto" (judged from the plan) or one of pmk_nb.indoorgml.units.UNIT_SCALE
    not_windows: tuple[str, ...] = ()  # cell names or ids the window/sill rule must leave navigable
    layers: tuple[str, ...] = ()  # space layers (ids or names) drawn instead of the navigable one
    crs: str = "auto"  # the coordinates' frame (--crs): auto, local, or a CRS name

    def to_json(self) -> dict[str, Any]:
        layers = {"layers": list(self.layers)} if self.layers else {}  # only when asked: older readers ignore it
        crs = {"crs": self.crs} if self.crs != "auto" else {}
        return {"unit": self.unit, "not_windows": list(self.not_windows), **layers, **crs}


def read_choices(doc: Mapping[str, Any] | None) -> ConvertChoices | None:
    """The choices one rooms file recorded, or None (written before they were kept, or damaged: a rooms
    file is ours, but a copied or hand-edited one must not break the screen)."""
    raw = (doc or {}).get(CHOICES_KEY)
    if not isinstance(raw, Mapping):
        return None
    unit = raw.get("unit")
    words = raw.get("not_windows")
    layers = raw.get("layers", [])  # absent in rooms files written before --layer
    crs = raw.get("crs", "auto")  # absent unless --crs was given
    if unit not in UNIT_CHOICES or not _strings(words) or not _strings(layers) or not isinstance(crs, str):
        return None
    return ConvertChoices(str(unit), tuple(words), tuple(layers), crs)


def _strings(value: Any) -> TypeGuard[list[str]]:
    return isinstance(value, list) and all(isinstance(x, str) for x in value)


def last_choices(docs: Iterable[Mapping[str, Any] | None]) -> ConvertChoices:
    """What the map's last conversion used: every storey of one conversion records the same, so the first
    storey that recorded them says it; defaults when none did."""
    return next((c for c in map(read_choices, docs) if c is not None), ConvertChoices())


def window_cells(docs: Iterable[Mapping[str, Any] | None]) -> list[str]:
    """Names of the cells the storeys' reports took for windows or sills, in report order, each once."""
    names: dict[str, None] = {}
    for doc in docs:
        report = (doc or {}).get("accessibility") or {}
        for item in report.get("not_checked") or []:
            if isinstance(item, Mapping) and item.get("reason") == SKIP_WINDOW and isinstance(item.get("cell"), str):
                names.setdefault(item["cell"], None)
    return list(names)


def offered(choices: ConvertChoices, windows: Sequence[str]) -> list[tuple[str, bool]]:
    """The cells to offer as "not a window", ticked or not: those the user already kept navigable (they
    are no longer windows, so no report names them) and those the reports now take for windows."""
    kept = list(dict.fromkeys(choices.not_windows))
    return [(n, True) for n in kept] + [(n, False) for n in windows if n not in kept]
