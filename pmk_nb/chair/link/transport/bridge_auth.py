"""The link's side of rosbridge authentication (rosauth's ``auth`` op, :mod:`pmk_nb.rosauth`).

A chair whose rosbridge runs with ``authenticate:=true`` (a classroom seat's simulator in ``pmk hub``)
closes the socket of a client whose first op is not a granted ``auth``. The secret stays in its file
(readable only by its student): :class:`BridgeAuth` names the file and reads it at each connect, so a
profile never holds the secret itself. Every socket the link opens sends the op first: the probe, the
link's own socket (on each reconnect), the Stop's side channel and a recording's connection.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pmk_nb.errors import ChairLinkError
from pmk_nb.rosauth import auth_op, read_secret


class BridgeAuthError(ChairLinkError):
    """The chair's rosbridge authentication failed: the secret file unreadable (``secret_file`` set) or the
    ``auth`` op refused by the chair (the socket closed after it)."""

    def __init__(self, message: str, *, secret_file: Path, host: str, port: int, refused: bool) -> None:
        hint = (
            "this chair accepts only its own student's secret: check the profile's bridge secret file"
            if refused
            else "the secret file must exist and be readable by this user"
        )
        super().__init__(message, host=host, port=port, hint=hint)
        self.secret_file, self.refused = secret_file, refused


@dataclass(frozen=True)
class BridgeAuth:
    """Authenticate to the chair's rosbridge with the secret in ``secret_file``."""

    secret_file: Path

    def op(self, host: str, port: int) -> dict[str, Any]:
        """A fresh ``auth`` op (new random string, current time). Raises BridgeAuthError when unreadable."""
        try:
            secret = read_secret(self.secret_file)
        except (OSError, UnicodeDecodeError) as err:
            raise BridgeAuthError(
                f"Cannot read the chair's bridge secret {self.secret_file}: {err}",
                secret_file=self.secret_file,
                host=host,
                port=port,
                refused=False,
            ) from err
        return auth_op(secret, dest=host)

    def refused(self, host: str, port: int) -> BridgeAuthError:
        """The error for a chair that closed the socket after our ``auth`` op."""
        return BridgeAuthError(
            f"The chair at {host}:{port} refused this link's authentication (it closed the connection)",
            secret_file=self.secret_file,
            host=host,
            port=port,
            refused=True,
        )
