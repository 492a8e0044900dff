"""Make every ipycanvas message name its layer, so a page that connects late still draws the frames.

The ipycanvas behaviour worked around (ipycanvas 0.14.3, ``.venv/lib/python3.11/site-packages/
ipycanvas/canvas.py``): all canvases of a kernel share one ``_CanvasManager`` (``_CANVAS_MANAGER``,
line 262).  Its ``send_command`` (lines 219-244) emits a ``switchCanvas`` command only when the
target canvas differs from ``self._current_canvas``, the canvas it switched to last, remembered in
Python for the whole kernel.  The page keeps the matching state in its ``CanvasManagerModel``
(``currentCanvas``, set only by ``switchCanvas``) and draws each command on that canvas.

A page that did not see the last switch has no current canvas: Voilà drops the messages a kernel
sends before the page has connected, a reload or a second view starts with fresh models.  The live
view's frames after the first one draw only the dynamic layer, so the kernel never sends the switch
again and those frames go nowhere on that page (``this.currentCanvas`` is undefined) until something
draws on another layer.  ``on_client_ready`` does not cover it: it fires when the page's canvas
model is created, which may come before or after the frames in flight.

The fix: after each message the manager hands to its comm (``_send_custom``, lines 256-258, the one
funnel of batched and single commands), forget the current canvas, so the next message starts with
its own ``switchCanvas``.  A batched frame (``hold_canvas``) then costs one switch command (a few
bytes); commands within a message still switch only when the layer changes.  Installed once on the
shared manager, idempotent; the internals are touched in :mod:`pmk_nb.seams.ipycanvas_seam`.

Each batch also ends on a parking canvas (1 x 1, never shown).  The page's ``onCommand`` starts a
message's list of canvases to refresh with the canvas the previous message left current, and each
``switchCanvas`` adds its canvas again: a frame that starts by switching to the layer the last frame
drew on refreshed that layer twice, and a ``MultiCanvas`` composited each frame twice (measured on a
classroom page: 24 composites a second, each a clear and two full-size ``drawImage``, for 12 frames).
Ending each batch on the parking canvas leaves it current, so the next frame's layer is refreshed
once; the parking canvas's own refresh does nothing (no view, nothing listens to its frames).
"""

from __future__ import annotations

import logging
from typing import Any

from ipycanvas import Canvas
from ipycanvas.canvas import COMMANDS
from ipywidgets import widget_serialization

from pmk_nb.seams import canvas_manager, forget_layer_after_each_message

log = logging.getLogger(__name__)


class Parking:
    """The 1 x 1 canvas each batch ends on (made again if something closed it)."""

    def __init__(self, manager: Any) -> None:
        self._manager = manager
        self.canvas: Canvas | None = None

    def switch(self) -> list[Any]:
        """The ``switchCanvas`` command to the parking canvas, as ipycanvas writes one."""
        if self.canvas is None or self.canvas.comm is None:  # closed (Widget.close_all, a test's cleanup)
            self.canvas = Canvas(width=1, height=1, _canvas_manager=self._manager)
        return [COMMANDS["switchCanvas"], [widget_serialization["to_json"](self.canvas, None)]]


def make_messages_name_their_layer(canvas: Any) -> bool:
    """Install the fix on ``canvas``'s (shared) canvas manager; True when it is in place.

    False, with a warning logged, when ipycanvas's internals differ from the version this was
    written for (the page then may miss frames after a late connect, nothing else changes).
    """
    manager = canvas_manager(canvas)
    if manager is None or not forget_layer_after_each_message(manager, Parking(manager).switch):
        log.warning("ipycanvas internals changed: late-joining pages may miss live frames")
        return False
    return True
