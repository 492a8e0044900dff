"""ipycanvas internals (pinned: ipycanvas==0.14.3; tests/seams/test_ipycanvas_seam.py).

Touched: ``Canvas._canvas_manager`` (the kernel-wide ``_CanvasManager`` every canvas sends through),
``_CanvasManager._send_custom`` (the one funnel of batched and single commands) and
``_CanvasManager._current_canvas`` (the canvas it last switched to), and the batch format of
``hold_canvas`` (a list of ``[command, args, buffer count]`` lists) to end each batch with one more
command (a switch to a parking canvas). Why: see :mod:`pmk_nb.ui.live.canvas_fix`. The byte meter
(:mod:`pmk_nb.ui.live.frame_metrics`) wraps the manager's public ``send`` (ipywidgets' ``Widget.send``)
and needs only the manager from here.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

_MARK = "_pmk_forgets_layer"
TOUCHED = ("_canvas_manager", "_send_custom", "_current_canvas")


def canvas_manager(canvas: Any) -> Any | None:
    """The (shared) canvas manager ``canvas`` sends its commands through; None if ipycanvas moved it."""
    return getattr(canvas, "_canvas_manager", None)


def is_batch(command: Any) -> bool:
    """True for a ``hold_canvas`` batch (a list of commands), False for one command."""
    return isinstance(command, list) and bool(command) and isinstance(command[0], list)


def forget_layer_after_each_message(manager: Any, last: Callable[[], list[Any] | None] | None = None) -> bool:
    """After each message the manager hands to its comm, forget the canvas it switched to, so the next
    message starts with its own ``switchCanvas``. With ``last``, each batch also ends with the command
    ``last()`` returns (None: nothing added). Idempotent (a later ``last`` replaces an earlier one);
    False when the internals differ."""
    if not hasattr(manager, "_current_canvas") or not hasattr(manager, "_send_custom"):
        return False
    installed = getattr(manager._send_custom, _MARK, None)
    if installed is not None:
        if last is not None:
            installed[0] = last
        return True
    send_custom = manager._send_custom
    ending: list[Callable[[], list[Any] | None] | None] = [last]

    def send_then_forget_layer(command: Any, buffers: list[Any] | None = None) -> None:
        end = ending[0]
        extra = end() if end is not None and is_batch(command) else None
        if extra is not None:
            command = [*command, extra]
        try:
            send_custom(command, [] if buffers is None else buffers)
        finally:
            manager._current_canvas = None

    setattr(send_then_forget_layer, _MARK, ending)
    manager._send_custom = send_then_forget_layer
    return True
