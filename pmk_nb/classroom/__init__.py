"""A simulated chair per page for teaching (issue 26): ``pmk demo --classroom`` and ``pmk hub``.

No widgets and no serving here: the kernel of a classroom page (:mod:`pmk_nb.ui.classroom_page`)
asks for a seat, which starts its own :class:`~pmk_nb.sim.SimChair` in the kernel's process (so it
ends with the kernel, whatever ends it) and writes a per-kernel settings folder whose only profile
points at that chair; pages never share a chair.

* ``settings``: the class's settings file (``classroom.json``) that ``pmk demo --classroom`` and
  ``pmk hub`` write and every classroom kernel reads (map, SFTP key, chair cap), found through
  :data:`~pmk_nb.classroom.settings.CLASSROOM_ENV`.
* ``cap``: how many chairs may run at once (default from cores and memory) and the flock'ed file
  of live chairs that every kernel of the class counts in (dead pids do not count).
* ``seat``: one page's chair and settings folder: :func:`~pmk_nb.classroom.seat.take_seat`.
"""

from pmk_nb.classroom.cap import ChairCap, ClassroomFull, default_max_chairs
from pmk_nb.classroom.fleet import class_chairs
from pmk_nb.classroom.seat import Seat, take_seat
from pmk_nb.classroom.settings import (
    BRIDGE_SECRET_ENV,
    CLASSROOM_ENV,
    SEAT_DIR_ENV,
    SEAT_KEY_ENV,
    SETTINGS_FILE,
    SHARED_USER_ENV,
    ClassroomSettings,
    StudentFiles,
)

__all__ = [
    "BRIDGE_SECRET_ENV",
    "CLASSROOM_ENV",
    "SEAT_DIR_ENV",
    "SEAT_KEY_ENV",
    "SETTINGS_FILE",
    "SHARED_USER_ENV",
    "ChairCap",
    "ClassroomFull",
    "ClassroomSettings",
    "Seat",
    "StudentFiles",
    "class_chairs",
    "default_max_chairs",
    "settings",
    "take_seat",
]
