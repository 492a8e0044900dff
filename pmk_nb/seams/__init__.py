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
