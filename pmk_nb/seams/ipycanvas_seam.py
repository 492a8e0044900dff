"""ipycanvas internals (pinned: ipycanvas==0.14.3; tests/seams/test_ipycanvas_seam.py).

Touched: ``Canvas._canvas_manager`` (the kernel-wide ``_CanvasManager`` every canvas sends through),
``_CanvasManager._send_custom`` (the one funnel of batched and single commands) and
``_CanvasManager._current_canvas`` (the canvas it last switched to). Why: see
:mod:`pmk_nb.ui.live.canvas_fix`. The byte meter (:mod:`pmk_nb.ui.live.frame_metrics`) wraps the manager's
public ``send`` (ipywidgets' ``Widget.send``) and needs only the manager from here.
"""

from __future__ import annotations

from typing import Any

_MARK = "_pmk_forgets_layer"
TOUCHED = ("_canvas_manager", "_send_custom", "_current_canvas")


def canvas_manager(canvas: Any) -> Any | None:
    """The (shared) canvas manager ``canvas`` sends its commands through; None if ipycanvas moved it."""
    return getattr(canvas, "_canvas_manager", None)


def forget_layer_after_each_message(manager: Any) -> bool:
    """After each message the manager hands to its comm, forget the canvas it switched to, so the next
    message starts with its own ``switchCanvas``. Idempotent; False when the internals differ."""
    if not hasattr(manager, "_current_canvas") or not hasattr(manager, "_send_custom"):
        return False
    if getattr(manager._send_custom, _MARK, False):
        return True
    send_custom = manager._send_custom

    def send_then_forget_layer(command: Any, buffers: list[Any] | None = None) -> None:
        try:
            send_custom(command, [] if buffers is None else buffers)
        finally:
            manager._current_canvas = None

    setattr(send_then_forget_layer, _MARK, True)
    manager._send_custom = send_then_forget_layer
    return True
