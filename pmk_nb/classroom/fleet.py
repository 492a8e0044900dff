"""The class's chairs as profiles, for an instructor's Fleet panel (issue 26): every live seat's
simulated chair, read from the class's chair file (:class:`~pmk_nb.classroom.cap.ChairCap`), where
each seat notes its rosbridge port and its student.  Nothing is started here: the chairs are the
students' own, living with their pages.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.classroom.cap import ChairCap

if TYPE_CHECKING:
    from pmk_nb.chair import ChairProfile
    from pmk_nb.classroom.settings import ClassroomSettings


def seat_name(pid: int, facts: dict[str, object]) -> str:
    """A seat's chair as the instructor reads it: the student's name (JupyterHub), else the page's pid."""
    user = str(facts.get("user") or "").strip()
    return f"Seat of {user}" if user else f"Seat {pid}"


def class_chairs(settings: ClassroomSettings) -> list[ChairProfile]:
    """One profile per live seat that has said its port, in the order the seats were taken.

    A seat whose port is not noted yet (its chair still starting) is left out: the next read
    finds it.
    """
    from pmk_nb.chair import ChairProfile

    seats = ChairCap(Path(settings.state_dir), settings.max_chairs).live()
    out: list[ChairProfile] = []
    for pid, facts in sorted(seats.items(), key=lambda item: (_since(item[1]), item[0])):
        port = facts.get("ros_port")
        if not isinstance(port, int) or not 0 < port < 65536:
            continue
        out.append(ChairProfile(name=seat_name(pid, facts), host="127.0.0.1", port=port))
    return out


def _since(facts: dict[str, object]) -> float:
    since = facts.get("since")
    return float(since) if isinstance(since, int | float) else 0.0
