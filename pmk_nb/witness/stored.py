"""The witness's verdict as a rooms file keeps it (key ``witness``), read back strictly and put in plain words.

A rooms file is a file: an old one has no verdict, a hand-edited one may hold anything. Reading it
back checks every field (a screen shows "unreadable", never a traceback), and the words are built
here, without widgets, so the dashboard and its tests share them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from pmk_nb.errors import PmkError
from pmk_nb.witness.findings import Finding, FindingKind, WitnessReport

WITNESS_KEY = "witness"  # the rooms file's key (pmk_nb.library.convert writes it)
MAX_LINES = 50  # findings listed one per line; the rest are counted ("pmk check" lists them all)


class WitnessUnreadable(PmkError):
    """A stored verdict that is not what :meth:`WitnessReport.to_json` writes.

    Attributes:
        reason: which field is wrong and how.
    """

    def __init__(self, reason: str) -> None:
        super().__init__(f"witness verdict unreadable: {reason}", hint="Convert the map again, or check it.")
        self.reason = reason


class VerdictState(str, Enum):
    AGREES = "agrees"
    DISAGREES = "disagrees"
    NO_GRAPH = "no-graph"  # no usable navigation graph: leaks and transitions not judged
    NOT_WITNESSED = "not-witnessed"  # converted before the witness, or without the check
    UNREADABLE = "unreadable"


@dataclass(frozen=True)
class Verdict:
    """What to say about one map: a headline, one line per finding (numbered as in the witness's
    picture), how many more were left out, and the report when there is one."""

    state: VerdictState
    headline: str
    lines: tuple[str, ...] = ()
    more: int = 0
    report: WitnessReport | None = field(default=None, compare=False)


def _number(value: object, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise WitnessUnreadable(f"{what} is not a finite number ({value!r:.40})")
    return float(value)


def _text(value: object, what: str) -> str:
    if not isinstance(value, str):
        raise WitnessUnreadable(f"{what} is not text ({value!r:.40})")
    return value


def _texts(value: object, what: str) -> tuple[str, ...]:
    if not isinstance(value, list):
        raise WitnessUnreadable(f"{what} is not a list ({value!r:.40})")
    return tuple(_text(v, f"{what}[{i}]") for i, v in enumerate(value))


def _finding(value: object, i: int, storey: str) -> Finding:
    what = f"finding {i + 1}"
    if not isinstance(value, dict):
        raise WitnessUnreadable(f"{what} is not an object")
    try:
        kind = FindingKind(value.get("kind"))
    except ValueError:
        raise WitnessUnreadable(f"{what} has an unknown kind ({value.get('kind')!r:.40})") from None
    place = value.get("place")
    if not isinstance(place, list) or len(place) != 2:
        raise WitnessUnreadable(f"{what}: place is not [x, y]")
    return Finding(
        kind=kind,
        storey=_text(value.get("storey", storey), f"{what}: storey"),
        cells=_texts(value.get("cells"), f"{what}: cells"),
        names=_texts(value.get("names"), f"{what}: names"),
        place=(_number(place[0], f"{what}: x"), _number(place[1], f"{what}: y")),
        detail=_text(value.get("detail", ""), f"{what}: detail"),
        amount=_number(value.get("amount", 0.0), f"{what}: amount"),
    )


def report_from_json(value: object) -> WitnessReport:
    """The report :meth:`WitnessReport.to_json` wrote, every field checked.

    Raises:
        WitnessUnreadable: a field missing, of the wrong type, or an ``ok`` that contradicts the findings.
    """
    if not isinstance(value, dict):
        raise WitnessUnreadable(f"not an object ({type(value).__name__})")
    data: dict[str, Any] = value
    storey = _text(data.get("storey"), "storey")
    graph = data.get("graph")
    if not isinstance(graph, bool):
        raise WitnessUnreadable(f"graph is not true or false ({graph!r:.40})")
    counts = data.get("counts", {})
    if not isinstance(counts, dict) or not all(
        isinstance(k, str) and isinstance(n, int) and not isinstance(n, bool) for k, n in counts.items()
    ):
        raise WitnessUnreadable("counts is not a table of whole numbers")
    findings = data.get("findings")
    if not isinstance(findings, list):
        raise WitnessUnreadable(f"findings is not a list ({findings!r:.40})")
    report = WitnessReport(
        storey=storey,
        chair_width=_number(data.get("chair_width", 0.0), "chair_width"),
        resolution=_number(data.get("resolution", 0.0), "resolution"),
        graph=graph,
        findings=[_finding(f, i, storey) for i, f in enumerate(findings)],
        counts=dict(counts),
    )
    if "ok" in data and data["ok"] is not report.ok:
        raise WitnessUnreadable(f"ok is {data['ok']!r:.20} but the findings say {report.ok}")
    return report


def _plural(n: int) -> str:
    return f"{n} finding{'' if n == 1 else 's'}"


def verdict_of(report: WitnessReport) -> Verdict:
    """A report in plain words."""
    if report.findings:
        lines = tuple(f.describe() for f in report.findings[:MAX_LINES])
        head = f"The map DISAGREES with the plan: {_plural(len(report.findings))}"
        if report.only_narrow:
            head = f"The chair does not fit through {len(report.findings)} door(s) of the map (a point does)"
        return Verdict(
            VerdictState.DISAGREES,
            head,
            lines,
            len(report.findings) - len(lines),
            report,
        )
    if not report.graph:
        head = "The plan has no usable navigation graph: the map's rooms were checked, leaks and doors were not"
        return Verdict(VerdictState.NO_GRAPH, head, report=report)
    return Verdict(VerdictState.AGREES, "The map agrees with the plan", report=report)


def stored_verdict(doc: dict[str, Any] | None) -> Verdict:
    """The verdict a map's rooms file keeps (``doc``: the file as read, None when it has none)."""
    if doc is None or WITNESS_KEY not in doc:
        return Verdict(VerdictState.NOT_WITNESSED, "This map has not been witnessed: check it against the plan")
    try:
        return verdict_of(report_from_json(doc[WITNESS_KEY]))
    except WitnessUnreadable as err:
        return Verdict(VerdictState.UNREADABLE, str(err.message))
