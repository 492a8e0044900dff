"""Choosing the length unit of a file that does not say (almost no IndoorGML file in the wild does).

``unit="auto"`` weighs every size the plan carries. Each kind of measure has a plausible range in
metres (m² for areas) and a weight; under each candidate unit, a kind earns its weight times the share
of its items that fall in the range, so one odd door does not sink a plan and thirty good ones count
for more than their median:

* door widths (door boundaries and door cells), 0.5-3 m - weight 4: a wheelchair map is useless when
  doors are 0.09 m or 9 m wide;
* door heights (z extent of 3D doors), 1.8-3 m - 1;
* cell heights (z_max - z_min of the larger half of the 3D cells: rooms, not windows), 2.2-6 m - 2;
* storey heights (floor to floor between the levels the rooms start at), 2.2-6 m - 1;
* stair risers (treads of a stair drawn as a solid, see :func:`footprint.stepped`), 0.1-0.26 m - 2
  (steep cellar and attic stairs rise a quarter metre; FJK-Haus's cellar stair is drawn at 0.25 m);
* room areas (the larger half of the free cells), 4-200 m² - 1 (rooms range from closets to halls);
* corridor widths (the mean width of TransitionSpace cells), 0.8-8 m - 1;
* faces a transition crosses (its duality), 0.5-3 m - 0.5: some exporters draw them as the door, others
  as the whole wall, so they count little (and are never called a conflict);
* the plan's extent, 5-500 m - 1;
* a known exporter (a comment such as "CityGML to IndoorGML") or a metric projected CRS in srsName - 6.

The unit with the highest score wins (ties: the unit the extent alone suggests, then metres); the
reason says which evidence agreed and how many items. ALMA files are centimetres (thesis ch. 3.2).
Kinds whose items mostly fall outside their range at the chosen unit are named in ``conflict`` with
the unit they fit; a heavy kind (weight 2+) even when it fits none, a light one that fits no unit is
only odd (PNU 201: doors and extent say metres, its 20-unit storeys fit no unit), so nobody quietly
gets 20 m storeys. :func:`unit_suspect` judges any unit, chosen or given by hand: when
most doors are absurd in it and fit another unit, ``pmk check`` names the unit before any door.
"""

from __future__ import annotations

from dataclasses import dataclass, field

UNIT_SCALE: dict[str, float] = {"m": 1.0, "dm": 0.1, "cm": 0.01, "mm": 0.001}
UNIT_CHOICES = ("auto", *UNIT_SCALE)
UNIT_WORDS = {"m": "metres", "dm": "decimetres", "cm": "centimetres", "mm": "millimetres"}
DOOR_RANGE = (0.5, 3.0)  # 0.5: narrow closet and toilet doors are real, and the check must name them
MOSTLY = 0.5  # a kind agrees with a unit when more than half its items fit
STRONG = 2  # a kind this heavy (door widths, cell heights, risers) is named even when it fits no unit
SLACK = 1e-9  # 80 m² drawn in decimetres is 80.00000000001 m²: range ends are inclusive up to rounding


@dataclass(frozen=True)
class Clue:
    """One kind of evidence: its items in file units, the plausible range in metres (or m²), a weight."""

    name: str  # plural words: "door widths"
    values: tuple[float, ...]
    low: float
    high: float
    weight: float
    power: int = 1  # 2 for areas

    def metres(self, unit: str, v: float | None = None) -> float:
        """``v`` (default: the median item) in metres (m²) under ``unit``."""
        if v is None:
            s = sorted(self.values)
            v = s[len(s) // 2]
        return v * UNIT_SCALE[unit] ** self.power

    def agree(self, unit: str) -> int:
        """How many items fall in the plausible range under ``unit``."""
        f = UNIT_SCALE[unit] ** self.power
        lo, hi = self.low * (1 - SLACK), self.high * (1 + SLACK)
        return sum(1 for v in self.values if lo <= v * f <= hi)

    def share(self, unit: str) -> float:
        return self.agree(unit) / len(self.values) if self.values else 0.0

    def fits(self, unit: str) -> bool:
        return self.share(unit) > MOSTLY

    def points(self, unit: str) -> float:
        return self.weight * self.share(unit)

    def size(self, unit: str) -> str:
        """The median item under ``unit`` in words: "0.9 m" / "20 m²"."""
        return f"{self.metres(unit):.3g} m{'²' if self.power == 2 else ''}"

    def describe(self, unit: str) -> str:
        """Which items agreed with ``unit``: "9 of 10 door widths (median 0.9 m)"."""
        n = len(self.values)
        if n == 1:
            return f"{self.name} {self.size(unit)}"
        return f"{self.agree(unit)} of {n} {self.name} (median {self.size(unit)})"


def _positive(values: list[float]) -> tuple[float, ...]:
    """The sizes a clue can use: a 2D cell has no height (0)."""
    return tuple(v for v in values if v > 0)


@dataclass
class UnitEvidence:
    """What the plan offers to judge its unit by (all in file units)."""

    door_widths: list[float] = field(default_factory=list)
    cell_heights: list[float] = field(default_factory=list)
    corridor_widths: list[float] = field(default_factory=list)
    room_areas: list[float] = field(default_factory=list)
    extent: float = 0.0
    door_heights: list[float] = field(default_factory=list)
    storey_heights: list[float] = field(default_factory=list)
    stair_risers: list[float] = field(default_factory=list)
    passage_widths: list[float] = field(default_factory=list)  # faces a transition crosses
    exporter: tuple[str, str] | None = None  # (unit, what the file says: "written by ...") for a known writer

    def clues(self) -> list[Clue]:
        out = [
            Clue("door widths", _positive(self.door_widths), *DOOR_RANGE, 4),
            Clue("door heights", _positive(self.door_heights), 1.8, 3.0, 1),
            Clue("cell heights", _positive(self.cell_heights), 2.2, 6.0, 2),
            Clue("storey heights", _positive(self.storey_heights), 2.2, 6.0, 1),
            Clue("stair risers", _positive(self.stair_risers), 0.1, 0.26, 2),
            Clue("room areas", _positive(self.room_areas), 4.0, 200.0, 1, power=2),
            Clue("corridor widths", _positive(self.corridor_widths), 0.8, 8.0, 1),
            Clue("transition faces", _positive(self.passage_widths), *DOOR_RANGE, 0.5),
            Clue("plan extent", _positive([self.extent]), 5.0, 500.0, 1),
        ]
        return [c for c in out if c.values]

    def score(self, unit: str) -> float:
        """The weight of the evidence that agrees with ``unit`` (see the module docstring)."""
        total = sum(c.points(unit) for c in self.clues())
        if self.exporter is not None and self.exporter[0] == unit:
            total += EXPORTER_WEIGHT
        return total


EXPORTER_WEIGHT = 6.0


@dataclass(frozen=True)
class UnitSuspect:
    """The unit, before any door, is the likely fault: most doors are absurd in it and fit another unit."""

    unit: str  # the unit the plan was read in
    better: str  # the unit the doors fit
    probable: bool  # the whole plan fits ``better`` better (else only the doors do: a doubt)
    door_width: float  # median door width in metres under ``unit``
    doors_wrong: int  # doors outside 0.5-3 m under ``unit``
    doors: int
    message: str  # plain words, with the fix (--unit)


@dataclass(frozen=True)
class UnitChoice:
    unit: str
    reason: str
    conflict: str = ""  # plain words when some evidence disagrees with the choice
    suspect: UnitSuspect | None = None  # the doors are absurd in this unit and fit another (see unit_suspect)


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
    scores = {u: evidence.score(u) for u in UNIT_SCALE}
    unit = max(UNIT_SCALE, key=lambda u: (round(scores[u], 6), u == by_extent, u == "m"))
    said = [c.describe(unit) for c in clues if c.fits(unit)]
    if evidence.exporter is not None and evidence.exporter[0] == unit:
        said.insert(0, evidence.exporter[1])
    if not said:
        return UnitChoice(unit, f"auto: no size looks like a building in any unit; by the plan extent -> {unit}")
    runner = max((u for u in UNIT_SCALE if u != unit), key=lambda u: scores[u])
    reason = (
        f"auto: {UNIT_WORDS[unit]} ({'; '.join(said)}; score {scores[unit]:.1f}, "
        f"next {UNIT_WORDS[runner]} {scores[runner]:.1f})"
    )
    return UnitChoice(unit, reason, _conflict(evidence, unit), unit_suspect(evidence, unit))


def _conflict(evidence: UnitEvidence, unit: str) -> str:
    """Plain words for the evidence that disagrees with ``unit`` ('' when none does)."""
    clues = evidence.clues()
    agreeing = [c.name for c in clues if c.fits(unit)]
    if evidence.exporter is not None and evidence.exporter[0] == unit:
        agreeing.insert(0, "writer named in the file")
    against = []
    for c in clues:
        if c.fits(unit) or c.weight < 1:  # a weak kind (transition faces) is no conflict
            continue
        here = f"the {c.name} are {c.size(unit)} in {UNIT_WORDS[unit]} ({c.agree(unit)} of {len(c.values)} fit)"
        others = sorted((u for u in UNIT_SCALE if c.fits(u)), key=c.share, reverse=True)
        if others:
            against.append(f"{here}: they say {UNIT_WORDS[others[0]]} ({c.describe(others[0])})")
        elif c.weight >= STRONG:  # odd in every unit: worth saying for the sizes a building is made to
            sq = "²" if c.power == 2 else ""
            against.append(f"{here} and fit no unit (expected {c.low:g}-{c.high:g} m{sq})")
    if evidence.exporter is not None and evidence.exporter[0] != unit:
        against.append(f"the file is {evidence.exporter[1]}, which means {UNIT_WORDS[evidence.exporter[0]]}")
    if not against:
        return ""
    because = f" because of the {', '.join(agreeing)}" if agreeing else ""
    return (
        f"The unit evidence disagrees: {UNIT_WORDS[unit]} was chosen{because}, but {'; and '.join(against)}. "
        "If the maps come out the wrong size, choose the unit by hand."
    )


def unit_suspect(evidence: UnitEvidence, unit: str) -> UnitSuspect | None:
    """Is ``unit`` the fault behind absurd doors? A suspect when most doors fall outside 0.5-3 m in it
    but fit another unit. *Probable* when that unit also scores higher overall (its rooms, heights and
    extent make sense too: a unit given by hand that is wrong); else a doubt worth naming before any
    door (the doors say one unit, the rest another)."""
    doors = next((c for c in evidence.clues() if c.name == "door widths"), None)
    if doors is None or doors.fits(unit):
        return None
    others = [u for u in UNIT_SCALE if u != unit and doors.fits(u)]
    if not others:
        return None
    better = max(others, key=evidence.score)
    probable = evidence.score(better) > evidence.score(unit)
    n, wrong = len(doors.values), len(doors.values) - doors.agree(unit)
    width = doors.metres(unit)
    lo, hi = DOOR_RANGE
    who = "all doors are" if wrong == n else f"{wrong} of {n} doors are not {lo:g}-{hi:g} m wide; the median door is"
    symptom = f"{who} {width:.2g} m wide in {UNIT_WORDS[unit]}"
    if probable:
        fits = "; ".join(c.describe(better) for c in evidence.clues() if c.fits(better))
        said = f"the plan is probably in {UNIT_WORDS[better]} ({fits})"
    else:
        rest = ", ".join(c.name for c in evidence.clues() if c.fits(unit)) or "the plan's other sizes"
        said = f"in {UNIT_WORDS[better]} they would be {doors.size(better)}, but the {rest} say {UNIT_WORDS[unit]}"
    return UnitSuspect(unit, better, probable, width, wrong, n, f"{symptom}: {said}; try --unit {better}")
