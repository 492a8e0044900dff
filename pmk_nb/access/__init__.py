"""Wheelchair accessibility of a written map: passable transitions, narrow doors, unreachable rooms, leaks.

Public API: :func:`check_storey` / :class:`StoreyReport` (:mod:`.report`); :func:`check_building`,
:func:`check_map`, :func:`check_grid` and :func:`check_plan_file` (:mod:`.check`); the pixel tools in :mod:`.pixels`.
"""

from pmk_nb.access.check import (
    check_building,
    check_chair_width,
    check_grid,
    check_map,
    check_plan_file,
    profile_chair_width,
)
from pmk_nb.access.report import DEFAULT_CHAIR_WIDTH, SKIP_OUTSIDE, LinkCheck, NotChecked, StoreyReport, check_storey
from pmk_nb.access.sidecar import NoRoomsFile, StoreyPlanFile, read_sidecar, sidecar_doc, sidecar_json, sidecar_path
from pmk_nb.access.widths import free_width
from pmk_nb.pixels import disc_radius_px, erode  # re-exported: the guide erodes with them

__all__ = [
    "DEFAULT_CHAIR_WIDTH",
    "SKIP_OUTSIDE",
    "LinkCheck",
    "NoRoomsFile",
    "NotChecked",
    "StoreyPlanFile",
    "StoreyReport",
    "check_building",
    "check_chair_width",
    "check_grid",
    "check_map",
    "check_plan_file",
    "check_storey",
    "disc_radius_px",
    "erode",
    "free_width",
    "profile_chair_width",
    "read_sidecar",
    "sidecar_doc",
    "sidecar_json",
    "sidecar_path",
]
