"""The witness: a written map judged against its plan, sharing no decision with the converter.

Public API: :func:`witness_map` and :func:`witness_grid` (:mod:`.check`), :func:`witness_storey`
(:mod:`.storey`), the findings (:mod:`.findings`), the picture of the findings (:mod:`.picture`),
the verdict a rooms file keeps, in words (:mod:`.stored`).
"""

from pmk_nb.witness.check import PlanChanged, PlanNotFound, find_plan, witness_grid, witness_map
from pmk_nb.witness.findings import Finding, FindingKind, WitnessReport
from pmk_nb.witness.picture import findings_png, write_picture
from pmk_nb.witness.stored import (
    WITNESS_KEY,
    Verdict,
    VerdictState,
    WitnessUnreadable,
    report_from_json,
    stored_verdict,
    verdict_of,
)
from pmk_nb.witness.storey import witness_storey

__all__ = [
    "WITNESS_KEY",
    "Finding",
    "FindingKind",
    "PlanChanged",
    "PlanNotFound",
    "Verdict",
    "VerdictState",
    "WitnessReport",
    "WitnessUnreadable",
    "find_plan",
    "findings_png",
    "report_from_json",
    "stored_verdict",
    "verdict_of",
    "witness_grid",
    "witness_map",
    "witness_storey",
    "write_picture",
]
