"""pmk_nb.ui: the ipywidgets dashboard (Home / Maps / Settings) for JupyterLab and the Voilà kiosk.

``build_app`` is imported lazily so that ``pmk`` commands living here (``pmk dashboard``) stay cheap.
Subpackages by screen and layer (issue 25): ``home``, ``maps``, ``settings``, ``kiosk`` (the screens);
``drive``, ``goals``, ``rooms``, ``fleet``, ``plots``, ``record`` (Home's panels); ``live`` (the canvas);
``common`` (session state, widgets, style). ``app`` is the shell. Their ``__init__`` files import nothing.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.ui.app import build_app
    from pmk_nb.ui.common.context import AUTOSTART_ENV, AppContext
    from pmk_nb.ui.common.page_lifecycle import PAGE_GONE_MSG
    from pmk_nb.ui.kiosk.pin import KIOSK_ENV

_WHERE = {
    "build_app": "app",
    "AUTOSTART_ENV": "common.context",
    "AppContext": "common.context",
    "PAGE_GONE_MSG": "common.page_lifecycle",
    "KIOSK_ENV": "kiosk.pin",
}

__all__ = [
    "AUTOSTART_ENV",
    "KIOSK_ENV",
    "PAGE_GONE_MSG",
    "AppContext",
    "build_app",
]


__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
