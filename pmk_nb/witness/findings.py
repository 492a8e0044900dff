"""What the witness found: one typed finding per disagreement between the written map and the plan."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum


class FindingKind(str, Enum):
    """Each way a written map can disagree with its plan."""

    ROOM_NOT_FREE = "room-not-free"  # a navigable cell's interior is not free in the map
    OBSTACLE_FREE = "obstacle-free"  # a non-navigable cell's interior is free in the map
    LEAK = "leak"  # two cells the graph does not join are joined in the map
    BLOCKED = "blocked"  # a transition with no way through in the map, not even for a point
    NARROW = "narrow"  # a transition a point passes but the chair does not (a narrow door, or drawn narrow)
    NO_WAY_THROUGH = "no-way-through"  # a passage cell (a door slab) the chair cannot cross between its rooms
    OUTSIDE_MAP = "outside-map"  # a cell the map does not cover
    OVERLAP = "overlap"  # two navigable cells overlap in the plan
    IMPLAUSIBLE = "implausible"  # sizes that no building has in the chosen unit

    @property
    def words(self) -> str:
        return _WORDS[self]


_WORDS = {
    FindingKind.ROOM_NOT_FREE: "room not free",
    FindingKind.OBSTACLE_FREE: "obstacle drawn as floor",
    FindingKind.LEAK: "leak",
    FindingKind.BLOCKED: "blocked",
    FindingKind.NARROW: "narrower than the chair",
    FindingKind.NO_WAY_THROUGH: "no way through",
    FindingKind.OUTSIDE_MAP: "outside the map",
    FindingKind.OVERLAP: "overlapping cells",
    FindingKind.IMPLAUSIBLE: "implausible size",
}


@dataclass(frozen=True)
class Finding:
    """One disagreement, named by its cells (ids and names) and placed in the map frame (metres)."""

    kind: FindingKind
    storey: str
    cells: tuple[str, ...]
    names: tuple[str, ...]
    place: tuple[float, float]
    detail: str
    amount: float = 0.0  # what was measured: a share of pixels, square metres, or metres

    def describe(self) -> str:
        who = " and ".join(self.names) if self.names else "the storey"
        return f"{self.kind.words}: {who} at ({self.place[0]:.2f}, {self.place[1]:.2f}) m: {self.detail}"

    def to_json(self) -> dict[str, object]:
        return {
            "kind": self.kind.value,
            "storey": self.storey,
            "cells": list(self.cells),
            "names": list(self.names),
            "place": [round(self.place[0], 3), round(self.place[1], 3)],
            "detail": self.detail,
            "amount": round(self.amount, 4),
        }


@dataclass
class WitnessReport:
    """One storey's verdict on the written map. ``ok`` is a statement about the written files."""

    storey: str
    chair_width: float
    resolution: float
    graph: bool  # False: no usable navigation graph, so leaks and transitions were not judged
    findings: list[Finding] = field(default_factory=list)
    counts: dict[str, int] = field(default_factory=dict)  # what was looked at: rooms, obstacles, pairs, links

    @property
    def ok(self) -> bool:
        return self.graph and not self.findings

    @property
    def only_narrow(self) -> bool:
        """Every finding is a way a point passes and the chair does not: the map may well be right and the
        door narrow in the building too, so it is not called a disagreement (still not "ok")."""
        return bool(self.findings) and all(f.kind is FindingKind.NARROW for f in self.findings)

    def summary(self) -> str:
        looked = ", ".join(f"{n} {what}" for what, n in self.counts.items())
        head = f"witness, storey {self.storey}"
        if self.only_narrow:
            return f"{head}: {len(self.findings)} transition(s) narrower than the chair in the map ({looked})"
        if self.findings:
            return f"{head}: the map DISAGREES with the plan: {len(self.findings)} finding(s) ({looked})"
        if not self.graph:
            return f"{head}: no usable navigation graph: leaks and transitions not judged ({looked})"
        return f"{head}: the map agrees with the plan ({looked})"

    def to_json(self) -> dict[str, object]:
        return {
            "storey": self.storey,
            "ok": self.ok,
            "graph": self.graph,
            "chair_width": self.chair_width,
            "resolution": self.resolution,
            "counts": dict(self.counts),
            "findings": [f.to_json() for f in self.findings],
        }
