"""The ipycanvas internals pmk_nb/seams/ipycanvas_seam.py touches are still there, in the pinned version."""

from __future__ import annotations

import inspect
import json

import ipycanvas
from ipycanvas import Canvas
from ipycanvas import canvas as canvas_module

from pmk_nb.seams.ipycanvas_seam import TOUCHED, canvas_manager, forget_layer_after_each_message
from tests.seam_pins import assert_pinned_and_installed


def test_installed_ipycanvas_is_the_pinned_version() -> None:
    assert_pinned_and_installed("ipycanvas")
    assert ipycanvas.__version__ == "0.14.3"


def test_every_canvas_sends_through_the_shared_manager_funnel() -> None:
    assert TOUCHED == ("_canvas_manager", "_send_custom", "_current_canvas")
    manager_cls = canvas_module._CanvasManager
    send_command = inspect.getsource(manager_cls.send_command)
    assert "if self._current_canvas is not canvas:" in send_command  # a switch only on a change
    assert "self._send_custom(command, buffers)" in send_command
    assert "self._send_custom(self._commands_cache, self._buffers_cache)" in inspect.getsource(manager_cls.flush)
    assert "self.send(metadata, buffers=[command_buffer] + buffers)" in inspect.getsource(manager_cls._send_custom)
    a, b = Canvas(width=4, height=4), Canvas(width=4, height=4)
    assert canvas_manager(a) is canvas_manager(b) is canvas_module._CANVAS_MANAGER


def test_the_layer_is_forgotten_after_each_message() -> None:
    manager = canvas_manager(Canvas(width=4, height=4))
    assert forget_layer_after_each_message(manager) and forget_layer_after_each_message(manager)  # idempotent
    sent = []
    original_send = manager.send
    manager.send = lambda content, buffers=None: sent.append(len(buffers or []))
    try:
        Canvas(width=4, height=4).fill_rect(0, 0, 1, 1)
    finally:
        manager.send = original_send
    assert manager._current_canvas is None and len(sent) == 2  # the switch, then the command


def test_unknown_internals_are_refused_not_patched() -> None:
    class Other:
        pass

    assert canvas_manager(Other()) is None and not forget_layer_after_each_message(Other())


def test_a_batch_ends_with_the_extra_command_and_single_commands_stay_alone() -> None:
    from ipycanvas import hold_canvas

    canvas = Canvas(width=4, height=4)  # hold_canvas holds the shared manager
    manager = canvas_manager(canvas)
    extra = [canvas_module.COMMANDS["beginPath"], []]
    assert forget_layer_after_each_message(manager)
    assert forget_layer_after_each_message(manager, lambda: extra)  # a later end replaces none
    sent = []
    original_send = manager.send
    manager.send = lambda content, buffers=None: sent.append(bytes(memoryview(buffers[0])))
    try:
        with hold_canvas():
            canvas.fill_rect(0, 0, 1, 1)
        canvas.fill_rect(0, 0, 1, 1)  # not held: the switch and the command, each alone
    finally:
        manager.send = original_send
        forget_layer_after_each_message(manager, lambda: None)
    batch = json.loads(sent[0])
    assert batch[-1] == extra and len(batch) == 3  # switch, fillRect, the extra
    switch, fill = canvas_module.COMMANDS["switchCanvas"], canvas_module.COMMANDS["fillRect"]
    assert [json.loads(m)[0] for m in sent[1:]] == [switch, fill]
