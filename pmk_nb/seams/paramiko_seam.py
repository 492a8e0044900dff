"""paramiko internals (pinned: paramiko==5.1.0; tests/seams/test_paramiko_seam.py).

Touched: ``SFTPClient._convert_status(msg)``, where paramiko turns a status reply into an exception
(or nothing for OK). It maps the codes it knows to errno and every other one to a bare ``IOError``
holding only the server's text, so the code is read here first, from the same message, and the
message is rewound for paramiko.
"""

from __future__ import annotations

from typing import Any, ClassVar

import paramiko

TOUCHED = ("_convert_status",)


class StatusHookSFTPClient(paramiko.SFTPClient):  # type: ignore[misc]  # paramiko ships no type hints
    """An SFTP client that calls :meth:`on_status` with each status reply's code and text before
    paramiko converts it; a subclass raises its own typed error there (or returns: paramiko's way)."""

    hooked_codes: ClassVar[frozenset[int]] = frozenset()  # codes on_status is called for

    def on_status(self, code: int, text: str) -> None:
        """Raise for ``code`` (one of :attr:`hooked_codes`); returning lets paramiko convert it."""

    def _convert_status(self, msg: Any) -> None:
        start = msg.packet.tell()
        code = msg.get_int()
        if code in self.hooked_codes:
            self.on_status(code, msg.get_text())
        msg.packet.seek(start)
        super()._convert_status(msg)
