"""The witness's verdict read back from a rooms file, strictly, and put in plain words (no widgets)."""

from __future__ import annotations

import copy
from typing import Any

import pytest

from pmk_nb.witness import (
    Finding,
    FindingKind,
    VerdictState,
    WitnessReport,
    WitnessUnreadable,
    report_from_json,
    stored_verdict,
    verdict_of,
)
from pmk_nb.witness.stored import MAX_LINES

LEAK = Finding(
    FindingKind.LEAK, "0", ("R1", "R2"), ("Waiting room", "Exam room 1"), (10.0, 2.6), "joined through the wall", 0.4
)


def _report(findings: list[Finding], graph: bool = True) -> WitnessReport:
    return WitnessReport("0", 0.7, 0.05, graph, findings, {"cells": 15, "transitions": 12})


def test_a_report_survives_its_json() -> None:
    report = _report([LEAK])
    back = report_from_json(report.to_json())
    assert back.to_json() == report.to_json()
    assert back.findings == [LEAK]


def test_agreeing_and_disagreeing_reports_in_words() -> None:
    agrees = stored_verdict({"witness": _report([]).to_json()})
    assert (agrees.state, agrees.headline, agrees.lines) == (VerdictState.AGREES, "The map agrees with the plan", ())
    disagrees = stored_verdict({"witness": _report([LEAK, LEAK]).to_json()})
    assert disagrees.state is VerdictState.DISAGREES
    assert disagrees.headline == "The map DISAGREES with the plan: 2 findings"
    assert disagrees.lines[0] == "leak: Waiting room and Exam room 1 at (10.00, 2.60) m: joined through the wall"
    assert verdict_of(_report([LEAK])).headline.endswith(": 1 finding")
    assert verdict_of(_report([], graph=False)).state is VerdictState.NO_GRAPH


def test_many_findings_are_counted_past_the_first_lines() -> None:
    verdict = verdict_of(_report([LEAK] * (MAX_LINES + 3)))
    assert (len(verdict.lines), verdict.more) == (MAX_LINES, 3)


@pytest.mark.parametrize("doc", [None, {}, {"rooms": []}])
def test_a_map_converted_before_the_witness_is_not_witnessed(doc: dict[str, Any] | None) -> None:
    verdict = stored_verdict(doc)
    assert verdict.state is VerdictState.NOT_WITNESSED and "not been witnessed" in verdict.headline


def _broken(path: str, value: object) -> dict[str, Any]:
    doc = copy.deepcopy(_report([LEAK]).to_json())
    where: Any = doc
    *parents, last = path.split(".")
    for key in parents:
        where = where[int(key)] if isinstance(where, list) else where[key]
    if isinstance(where, list):
        where[int(last)] = value
    else:
        where[last] = value
    return doc


@pytest.mark.parametrize(
    ("value", "field"),
    [
        ("garbage", "not an object"),
        (None, "not an object"),
        (_broken("findings", "many"), "findings"),
        (_broken("graph", "yes"), "graph"),
        (_broken("storey", 3), "storey"),
        (_broken("counts", {"cells": "x"}), "counts"),
        (_broken("findings.0.kind", "flood"), "unknown kind"),
        (_broken("findings.0.place", [1.0]), "place"),
        (_broken("findings.0.place", [1.0, float("nan")]), "finite"),
        (_broken("findings.0.names", "Waiting room"), "names"),
        (_broken("findings.0.cells", [1, 2]), "cells"),
        (_broken("findings.0", 7), "not an object"),
        (_broken("ok", True), "ok is True"),
    ],
)
def test_a_malformed_verdict_is_unreadable_not_a_crash(value: object, field: str) -> None:
    with pytest.raises(WitnessUnreadable) as caught:
        report_from_json(value)
    assert field in caught.value.reason
    verdict = stored_verdict({"witness": value})
    assert verdict.state is VerdictState.UNREADABLE and verdict.headline.startswith("witness verdict unreadable")
