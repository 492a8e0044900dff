"""The planned path as the live view draws it: the part still ahead of the chair (issue 29).

Pure (issue 25): the link (``pmk_nb.chair.link.streams.planpath``) follows the navigation stack's plan; what of
it is still to drive is plain geometry, beside the live view's other maths.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: The chair this close (m) to the path's end has arrived: the path is no longer drawn.
ARRIVED_M = 0.4


def ahead_of(points: npt.ArrayLike, chair: tuple[float, float] | None) -> npt.NDArray[np.float64]:
    """The part of the path still ahead of the chair: from the point nearest it to the end.

    Empty once the chair is within :data:`ARRIVED_M` of the end (Nav2 and move_base publish no
    empty path at the goal: the last plan would otherwise stay on the map for good).
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if chair is None or pts.shape[0] == 0:
        return pts
    here = np.asarray(chair, dtype=np.float64)
    if float(np.hypot(pts[-1, 0] - here[0], pts[-1, 1] - here[1])) <= ARRIVED_M:
        return pts[:0]
    nearest = int(np.argmin(np.hypot(pts[:, 0] - here[0], pts[:, 1] - here[1])))
    return np.vstack([here, pts[nearest:]])
