"""A classroom page's session (issue 26): its own simulated chair, and words saying so on the page.

Outside a class (no ``PMK_CLASSROOM`` in the kernel's environment) nothing changes.  In a class, the
page's settings folder is the one its seat made (:mod:`pmk_nb.classroom.seat`), with the class's map
current; a full class raises :class:`~pmk_nb.classroom.ClassroomFull`, which ``build_app`` shows as
the page's only content.
"""

from __future__ import annotations

from pathlib import Path

from pmk_nb.classroom import Seat, take_seat
from pmk_nb.classroom import settings as classroom_settings
from pmk_nb.ui.common.context import AppContext

_RATES = (
    "It waits, parked, until you drive it or send it somewhere. "
    f"Simulated at lower rates (odometry {classroom_settings.ODOM_RATE:g} Hz, laser "
    f"{classroom_settings.SCAN_RATE:g} Hz, map redrawn at most {classroom_settings.LIVE_FPS:g} times a second, "
    "only when something moved) so the whole class fits on one machine."
)
CLASSROOM_NOTE = f"Classroom: this chair is yours alone. {_RATES}"

#: ``pmk hub --shared-user``: said on every page, so no student believes their work private
SHARED_USER_NOTE = (
    "No isolation in this class: every student's notebooks run as one user, so code in any notebook can read "
    "the other students' files and drive their chairs. Do not keep anything private here. "
    f"This chair is your own simulated chair. {_RATES}"
)


class ClassroomContext(AppContext):
    """A classroom page's session: closing it (the page gone, :mod:`pmk_nb.ui.common.page_lifecycle`) also
    stops its chair and gives the seat back, even where the server keeps the kernel a while (a
    JupyterHub user's server culls idle kernels only after minutes)."""

    seat: Seat | None = None

    def close(self) -> None:
        super().close()
        if self.seat is not None:
            self.seat.close()


def classroom_context(maps_dir: str | Path | None) -> AppContext | None:
    """The session of a classroom page, its chair started; None when this kernel is not in a class.

    Raises:
        ClassroomFull: the class's chair cap is reached.
        SettingsError: the class's settings file cannot be read.
    """
    settings = classroom_settings.from_env()
    if settings is None:
        return None
    from pmk_nb.chair import PROFILES_FILE, ProfileStore
    from pmk_nb.library import MapsFolder

    seat = take_seat(settings)
    profiles = ProfileStore(seat.config_dir / PROFILES_FILE, secrets=False)
    maps = MapsFolder(Path(maps_dir) if maps_dir is not None else None)
    ctx = ClassroomContext(maps, profiles, config_dir=seat.config_dir)
    ctx.seat = seat
    ctx.live_fps = classroom_settings.LIVE_FPS
    ctx.set_current_map(settings.map_name, settings.map_yaml, settings.map_preview)
    if classroom_settings.shared_user():
        ctx.notify(SHARED_USER_NOTE, "warning")
    else:
        ctx.notify(CLASSROOM_NOTE)
    return ctx
