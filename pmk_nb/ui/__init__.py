"""pmk_nb.ui: the ipywidgets dashboard (Home / Maps / Settings) for JupyterLab and the Voilà kiosk.

``build_app`` is imported lazily so that ``pmk`` commands living here (``pmk dashboard``) stay cheap.
Subpackages by screen and layer (issue 25): ``home``, ``maps``, ``settings``, ``kiosk`` (the screens);
``drive``, ``goals``, ``rooms``, ``fleet``, ``plots``, ``record`` (Home's panels); ``live`` (the canvas);
``common`` (session state, widgets, style). ``app`` is the shell. Their ``__init__`` files import nothing.
"""

from __future__ import annotations

from typing import Any

__all__ = ["build_app"]


def __getattr__(name: str) -> Any:
    if name == "build_app":
        from pmk_nb.ui.app import build_app

        return build_app
    raise AttributeError(f"module 'pmk_nb.ui' has no attribute {name!r}")
