"""Choosing the length unit of a file that does not say (almost no IndoorGML file in the wild does).

``unit="auto"`` lets every kind of size the plan carries vote. Each kind has a plausible range in
metres (m² for areas); it fits a unit when more than half its items fall in the range under that unit
(so one odd door does not sink thirty good ones), and votes for the unit it fits best (for each unit it
fits equally well). The plan's extent fits two units (a 60-unit plan may be 60 m or 6 m across): it votes
for the largest unit in which the plan is at most 250 m across. A kind that fits no unit abstains.

* door widths (door boundaries and door cells), 0.5-3 m;
* door heights (z extent of 3D doors), 1.8-3 m;
* cell heights (z_max - z_min of the larger half of the 3D cells: rooms, not windows), 2.2-6 m;
* storey heights (floor to floor between the levels the rooms start at), 2.2-6 m;
* stair risers (treads of a stair drawn as a solid, see :func:`footprint.stepped`), 0.1-0.26 m
  (steep cellar and attic stairs rise a quarter metre; FJK-Haus's cellar stair is drawn at 0.25 m);
* room areas (the larger half of the free cells), 4-200 m² (rooms range from closets to halls);
* corridor widths (the mean width of TransitionSpace cells), 0.8-8 m;
* faces a transition crosses (its duality), 0.5-3 m - half a vote: some exporters draw them as the
  door, others as the whole wall (and they are never called a conflict);
* the plan's extent, 5-500 m;
* a known exporter (a comment such as "CityGML to IndoorGML").

The unit with the most votes wins: one kind, however heavy its items, cannot outvote three that agree
(issue 37: one door width said centimetres, the door height, the cell height and the extent metres).
Ties go to the unit the evidence weighs most for (:meth:`UnitEvidence.score`: doors count four times,
heights twice, a writer six), then to the unit the extent alone suggests, then metres. A metric
projected CRS named in ``srsName`` is no vote: GML says the coordinates are in that CRS's unit, metres.
Every vote is kept (:attr:`UnitChoice.votes`, ``Building.unit_votes``) and a disagreement is reported
with each vote. ALMA files are centimetres (thesis ch. 3.2). A heavy kind (weight 2+: door widths, cell
heights, risers) that fits no unit is a conflict too; a light one is only odd (PNU 201: doors and extent
say metres, its 20-unit storeys fit no unit), so nobody quietly gets 20 m storeys.
:func:`unit_suspect` judges any unit, chosen or given by hand: when most doors are absurd in it and fit
another unit, ``pmk check`` names the unit before any door.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field, replace

UNIT_SCALE: dict[str, float] = {"m": 1.0, "dm": 0.1, "cm": 0.01, "mm": 0.001}
UNIT_CHOICES = ("auto", *UNIT_SCALE)
UNIT_WORDS = {"m": "metres", "dm": "decimetres", "cm": "centimetres", "mm": "millimetres"}
DOOR_RANGE = (0.5, 3.0)  # 0.5: narrow closet and toilet doors are real, and the check must name them
MOSTLY = 0.5  # a kind agrees with a unit when more than half its items fit
EXTENT = "plan extent"
STRONG = 2  # a kind this heavy (door widths, cell heights, risers) is named even when it fits no unit
SLACK = 1e-9  # 80 m² drawn in decimetres is 80.00000000001 m²: range ends are inclusive up to rounding


@dataclass(frozen=True)
class UnitVote:
    """One piece of the unit evidence and the unit it says (``pmk info`` lists every vote)."""

    source: str  # "door widths", "plan extent", "writer named in the file"
    units: tuple[str, ...]  # the units it fits best (several when equally well); () abstains: fits none
    weight: float  # its say: 1, or 0.5 for faces a transition crosses
    detail: str  # what it measured: "4 of 4 door widths (median 0.9 m) in centimetres"


@dataclass(frozen=True)
class Clue:
    """One kind of evidence: its items in file units, the plausible range in metres (or m²), a weight."""

    name: str  # plural words: "door widths"
    values: tuple[float, ...]
    low: float
    high: float
    weight: float  # how much it weighs in a tie (see UnitEvidence.score)
    power: int = 1  # 2 for areas
    vote: float = 1.0  # its say in the vote: 1, or half for a kind that may measure something else

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

    def voted(self) -> UnitVote:
        """Its vote: the units it fits best (none: it abstains), and what it measured."""
        fits = [u for u in UNIT_SCALE if self.fits(u)]
        if not fits:
            sq = "²" if self.power == 2 else ""
            said = f"{self.name} {self.size('m')} in metres: no unit gives {self.low:g}-{self.high:g} m{sq}"
            return UnitVote(self.name, (), self.vote, said)
        best = max(map(self.share, fits))
        units = tuple(u for u in fits if self.share(u) >= best - 1e-9)
        return UnitVote(self.name, units, self.vote, f"{self.describe(units[0])} in {UNIT_WORDS[units[0]]}")

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
    crs: str = ""  # what the file says when its srsName names a metric projected CRS: the unit is metres

    def clues(self) -> list[Clue]:
        out = [
            Clue("door widths", _positive(self.door_widths), *DOOR_RANGE, 4),
            Clue("door heights", _positive(self.door_heights), 1.8, 3.0, 1),
            Clue("cell heights", _positive(self.cell_heights), 2.2, 6.0, 2),
            Clue("storey heights", _positive(self.storey_heights), 2.2, 6.0, 1),
            Clue("stair risers", _positive(self.stair_risers), 0.1, 0.26, 2),
            Clue("room areas", _positive(self.room_areas), 4.0, 200.0, 1, power=2),
            Clue("corridor widths", _positive(self.corridor_widths), 0.8, 8.0, 1),
            Clue("transition faces", _positive(self.passage_widths), *DOOR_RANGE, 0.5, vote=0.5),
            Clue(EXTENT, _positive([self.extent]), 5.0, 500.0, 1),
        ]
        return [c for c in out if c.values]

    def score(self, unit: str) -> float:
        """The weight of the evidence that agrees with ``unit`` (see the module docstring)."""
        total = sum(c.points(unit) for c in self.clues())
        if self.exporter is not None and self.exporter[0] == unit:
            total += EXPORTER_WEIGHT
        return total

    def votes(self) -> list[UnitVote]:
        """Every kind's vote, and the writer's when the file names one."""
        out = []
        for c in self.clues():
            vote = c.voted()
            if c.name == EXTENT and len(vote.units) > 1 and (u := _extent_unit(self.extent)) in vote.units:
                vote = replace(vote, units=(u,), detail=f"{c.describe(u)} in {UNIT_WORDS[u]}")  # one plan, one size
            out.append(vote)
        if self.exporter is not None:
            out.append(UnitVote("writer named in the file", (self.exporter[0],), 1.0, self.exporter[1]))
        return out

    def tally(self, unit: str) -> float:
        """The votes for ``unit``."""
        return tally(self.votes(), unit)


def tally(votes: Iterable[UnitVote], unit: str) -> float:
    """The votes among ``votes`` for ``unit``."""
    return sum(v.weight for v in votes if unit in v.units)


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
    votes: tuple[UnitVote, ...] = ()  # every piece of evidence and the unit it says (auto only)


LARGEST_PLAN = 250.0  # m: the plan's extent alone says the largest unit in which it is at most this wide


def _extent_unit(extent: float) -> str:
    """The unit the extent alone suggests: the largest in which the plan is at most 250 m across."""
    return next((u for u, f in UNIT_SCALE.items() if extent * f <= LARGEST_PLAN), "mm")


def choose_unit(*, alma: bool, alma_why: str, evidence: UnitEvidence) -> UnitChoice:
    """The unit for a file that does not give one; see the module docstring."""
    if alma:
        return UnitChoice("cm", f"auto: ALMA style ({alma_why}) -> centimetres")
    votes = tuple(evidence.votes())
    counts = {u: tally(votes, u) for u in UNIT_SCALE}
    scores = {u: evidence.score(u) for u in UNIT_SCALE}
    by_extent = _extent_unit(evidence.extent)

    def rank(u: str) -> tuple[float, float, bool, bool]:
        return (counts[u], round(scores[u], 6), u == by_extent, u == "m")

    unit = "m" if evidence.crs else max(UNIT_SCALE, key=rank)
    said = [v.detail for v in votes if unit in v.units]
    if evidence.crs:
        said.insert(0, evidence.crs)
    if not said:
        return UnitChoice(
            unit, f"auto: no size looks like a building in any unit; by the plan extent -> {unit}", votes=votes
        )
    runner = max((u for u in UNIT_SCALE if u != unit), key=rank)
    total = sum(v.weight for v in votes)
    tie = not evidence.crs and counts[unit] == counts[runner]
    reason = (
        f"auto: {UNIT_WORDS[unit]} ({'; '.join(said)}; {counts[unit]:g} of {total:g} votes, "
        f"next {UNIT_WORDS[runner]} {counts[runner]:g}"
        + (f"; a tie, the weightier evidence decides: {scores[unit]:.1f} to {scores[runner]:.1f}" if tie else "")
        + ")"
    )
    return UnitChoice(unit, reason, _conflict(evidence, unit), unit_suspect(evidence, unit), votes)


def _conflict(evidence: UnitEvidence, unit: str) -> str:
    """Plain words for the evidence that disagrees with ``unit`` ('' when none does), with every vote."""
    clues = evidence.clues()
    agreeing = [c.name for c in clues if c.fits(unit)]
    if evidence.exporter is not None and evidence.exporter[0] == unit:
        agreeing.insert(0, "writer named in the file")
    if evidence.crs:
        agreeing.insert(0, "CRS named in srsName")
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
        f"The votes: {vote_words(evidence.votes())}. If the maps come out the wrong size, choose the unit by hand."
    )


def vote_words(votes: Iterable[UnitVote]) -> str:
    """Every vote in one line: "metres 3 (door heights, cell heights, plan extent); centimetres 1 (door
    widths); no unit 1 (room areas)"."""
    by_unit: dict[str, list[UnitVote]] = {}
    for v in votes:
        for u in v.units or ("",):
            by_unit.setdefault(u, []).append(v)
    parts = []
    for u in (*UNIT_SCALE, ""):
        if u in by_unit:
            n = sum(v.weight for v in by_unit[u])
            parts.append(f"{UNIT_WORDS[u] if u else 'no unit'} {n:g} ({', '.join(v.source for v in by_unit[u])})")
    return "; ".join(parts)


def unit_suspect(evidence: UnitEvidence, unit: str) -> UnitSuspect | None:
    """Is ``unit`` the fault behind absurd doors? A suspect when most doors fall outside 0.5-3 m in it
    but fit another unit. *Probable* when that unit also has more votes (its rooms, heights and
    extent make sense too: a unit given by hand that is wrong); else a doubt worth naming before any
    door (the doors say one unit, the rest another)."""
    doors = next((c for c in evidence.clues() if c.name == "door widths"), None)
    if doors is None or doors.fits(unit):
        return None
    others = [u for u in UNIT_SCALE if u != unit and doors.fits(u)]
    if not others:
        return None
    better = max(others, key=lambda u: (evidence.tally(u), evidence.score(u)))
    probable = evidence.tally(better) > evidence.tally(unit)
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
