"""Wheelchair accessibility of a written map: passable transitions, narrow doors, unreachable rooms, leaks.

Public API: :func:`check_storey` / :class:`StoreyReport` (:mod:`.report`); :func:`check_building`,
:func:`check_map`, :func:`check_grid` and :func:`check_plan_file` (:mod:`.check`); the pixel tools in :mod:`.pixels`.
"""

from pmk_nb.access.report import DEFAULT_CHAIR_WIDTH, LinkCheck, NotChecked, StoreyReport, check_storey
from pmk_nb.access.widths import free_width

__all__ = ["DEFAULT_CHAIR_WIDTH", "LinkCheck", "NotChecked", "StoreyReport", "check_storey", "free_width"]
