"""Choosing the length unit of a file that does not say (no IndoorGML file in the wild does).

``unit="auto"`` weighs every piece of evidence the plan offers, in metres under each candidate unit:

* door widths (door boundaries and door cells), median in 0.5-3 m - weight 3: a wheelchair map is
  useless when doors are 0.15 m or 15 m wide;
* cell heights (z_max - z_min of the larger half of the 3D cells), median in 2.2-6 m - weight 2: a
  storey's height (windows and door cells are small and short, so they are left out);
* corridor widths (the short side of TransitionSpace cells), median in 0.8-8 m - weight 1;
* room areas (the larger half of the free cells), median in 2-500 m² - weight 1;
* the plan's extent, 3 m to 1 km - weight 1 (UTM-sized coordinates have a small extent too).

The unit with the highest score wins; ties go to the unit the extent alone suggests (<= 250 units ->
metres, <= 1000 -> decimetres, <= 100 000 -> centimetres, else millimetres). ALMA files are
centimetres (thesis ch. 3.2). When the winner fails a piece of evidence that another unit satisfies
(PNU 201: doors say metres, 20-unit storeys say decimetres), the choice is kept but the conflict is
said in plain words, so nobody quietly gets 20 m storeys.
"""

from __future__ import annotations

from dataclasses import dataclass, field

UNIT_SCALE: dict[str, float] = {"m": 1.0, "dm": 0.1, "cm": 0.01, "mm": 0.001}
UNIT_CHOICES = ("auto", *UNIT_SCALE)
UNIT_WORDS = {"m": "metres", "dm": "decimetres", "cm": "centimetres", "mm": "millimetres"}
DOOR_RANGE = (0.5, 3.0)


@dataclass(frozen=True)
class Clue:
    """One kind of evidence: its values in file units, the plausible range in metres (or m²), a weight."""

    name: str
    values: tuple[float, ...]
    low: float
    high: float
    weight: int
    power: int = 1  # 2 for areas

    @property
    def median(self) -> float:
        v = sorted(self.values)
        return v[len(v) // 2]

    def metres(self, unit: str) -> float:
        return self.median * UNIT_SCALE[unit] ** self.power

    def fits(self, unit: str) -> bool:
        return bool(self.values) and self.low <= self.metres(unit) <= self.high

    def describe(self, unit: str) -> str:
        sq = "²" if self.power == 2 else ""
        return f"{self.name} {self.metres(unit):.3g} m{sq}"


@dataclass
class UnitEvidence:
    """What the plan offers to judge its unit by (all in file units)."""

    door_widths: list[float] = field(default_factory=list)
    cell_heights: list[float] = field(default_factory=list)
    corridor_widths: list[float] = field(default_factory=list)
    room_areas: list[float] = field(default_factory=list)
    extent: float = 0.0

    def clues(self) -> list[Clue]:
        out = [
            Clue("median door width", tuple(self.door_widths), *DOOR_RANGE, 3),
            Clue("median cell height", tuple(h for h in self.cell_heights if h > 0), 2.2, 6.0, 2),
            Clue("median corridor width", tuple(self.corridor_widths), 0.8, 8.0, 1),
            Clue("median room area", tuple(self.room_areas), 2.0, 500.0, 1, power=2),
            Clue("plan extent", (self.extent,) if self.extent > 0 else (), 3.0, 1000.0, 1),
        ]
        return [c for c in out if c.values]


@dataclass(frozen=True)
class UnitChoice:
    unit: str
    reason: str
    conflict: str = ""  # plain words when some evidence disagrees with the choice


def _extent_unit(extent: float) -> str:
    for limit, unit in ((250.0, "m"), (1000.0, "dm"), (100_000.0, "cm")):
        if extent <= limit:
            return unit
    return "mm"


def choose_unit(*, alma: bool, alma_why: str, evidence: UnitEvidence) -> UnitChoice:
    """The unit for a file that does not give one; see the module docstring."""
    if alma:
        return UnitChoice("cm", f"auto: ALMA style ({alma_why}) -> centimetres")
    clues = evidence.clues()
    by_extent = _extent_unit(evidence.extent)

    def score(u: str) -> tuple[int, bool, bool]:
        return sum(c.weight for c in clues if c.fits(u)), u == by_extent, u == "m"

    unit = max(UNIT_SCALE, key=score)
    fitting = [c for c in clues if c.fits(unit)]
    if not fitting:
        return UnitChoice(unit, f"auto: no size looks like a building in any unit; by the plan extent -> {unit}")
    reason = f"auto: {UNIT_WORDS[unit]} ({'; '.join(c.describe(unit) for c in fitting)})"
    failed = [c for c in clues if not c.fits(unit)]
    conflicts = []
    for c in failed:
        others = [u for u in UNIT_SCALE if c.fits(u)]
        said = f"the {c.name} is {c.describe(unit).removeprefix(c.name + ' ')} in {UNIT_WORDS[unit]}"
        if others:
            conflicts.append(f"{said}, which fits {UNIT_WORDS[others[0]]} ({c.describe(others[0])}) better")
        else:
            sq = "²" if c.power == 2 else ""
            conflicts.append(f"{said} (expected {c.low:g}-{c.high:g} m{sq}; no unit gives that)")
    conflict = ""
    if conflicts:
        conflict = (
            f"The unit evidence conflicts: {UNIT_WORDS[unit]} was chosen because of the "
            f"{', '.join(c.name for c in fitting)}, but {'; and '.join(conflicts)}. "
            "If the maps come out the wrong size, choose the unit by hand."
        )
    return UnitChoice(unit, reason, conflict)
