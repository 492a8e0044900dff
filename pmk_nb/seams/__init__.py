"""Seams: the only places that touch another library's private members, one module per library.

Each library touched here is pinned exactly in ``pyproject.toml`` and has a seam test
(``tests/test_<library>_seam.py``) that fails when the installed version or a touched internal
changes, before a screen or a chair misbehaves. ``tests/project/test_private_access.py`` fails on a
``._private`` access anywhere else.

* ``roslibpy_seam``: the link's factory on a private loop, its reconnect switch and connect attempt;
  the ``status`` op handler; a ``Ros`` built without ``Ros.__init__``.
* ``ipycanvas_seam``: the canvas manager behind a canvas; every message names its layer.
* ``paramiko_seam``: an SFTP client that sees a status code before paramiko turns it into text.
* ``jupyter_server_seam``: how many websockets a kernel has; a refused connection forgotten.
* ``voila_seam``: the URL Voilà prints, rewritten (``https`` when it serves TLS).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.seams.ipycanvas_seam import canvas_manager, forget_layer_after_each_message
    from pmk_nb.seams.jupyter_server_seam import forget_open_session, kernel_connections
    from pmk_nb.seams.paramiko_seam import StatusHookSFTPClient
    from pmk_nb.seams.roslibpy_seam import FactorySeam, init_id_counter, install_status_handler
    from pmk_nb.seams.voila_seam import UrlHookVoila

_WHERE = {
    "canvas_manager": "ipycanvas_seam",
    "forget_layer_after_each_message": "ipycanvas_seam",
    "forget_open_session": "jupyter_server_seam",
    "kernel_connections": "jupyter_server_seam",
    "StatusHookSFTPClient": "paramiko_seam",
    "FactorySeam": "roslibpy_seam",
    "init_id_counter": "roslibpy_seam",
    "install_status_handler": "roslibpy_seam",
    "UrlHookVoila": "voila_seam",
}

__all__ = [
    "FactorySeam",
    "StatusHookSFTPClient",
    "UrlHookVoila",
    "canvas_manager",
    "forget_layer_after_each_message",
    "forget_open_session",
    "init_id_counter",
    "install_status_handler",
    "kernel_connections",
]


__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
