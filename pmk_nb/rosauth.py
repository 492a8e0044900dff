"""rosbridge v2's ``auth`` op as rosauth defines it: the one MAC, spoken by the link and checked by the simulator.

rosauth's ``authenticate`` service grants a client whose ``mac`` equals the hex SHA-512 of
``secret + client + dest + rand + t.sec + level + end.sec``, when ``t`` is within 5 s of the
server's clock and ``end`` is still ahead. rosbridge (``authenticate:=true``) closes the socket of a
client whose first op is not a granted ``auth``. roslibpy's ``Ros.authenticate`` sends the same op.
A secret is a file only its student can read (``pmk hub``): :func:`read_secret`.
"""

from __future__ import annotations

import hashlib
import hmac
import secrets
import time
from pathlib import Path
from typing import Any

#: how far a client's ``t`` may be from the server's clock (rosauth's 5 s)
CLOCK_SLACK_S = 5
#: how long a MAC this module makes is valid for
SESSION_S = 3600
LEVEL = "user"


def mac(secret: str, client: str, dest: str, rand: str, t: int, level: str, end: int) -> str:
    """rosauth's MAC over one request's fields."""
    text = f"{secret}{client}{dest}{rand}{int(t)}{level}{int(end)}"
    return hashlib.sha512(text.encode("utf-8")).hexdigest()


def auth_op(
    secret: str, client: str = "127.0.0.1", dest: str = "127.0.0.1", now: float | None = None
) -> dict[str, Any]:
    """A fresh ``auth`` op (a new random string and time each call) for a bridge holding ``secret``."""
    t = int(time.time() if now is None else now)
    rand, end = secrets.token_hex(16), t + SESSION_S
    return {
        "op": "auth",
        "mac": mac(secret, client, dest, rand, t, LEVEL, end),
        "client": client,
        "dest": dest,
        "rand": rand,
        "t": t,
        "level": LEVEL,
        "end": end,
    }


def _seconds(value: object) -> int | None:
    """A time as rosbridge clients send it: seconds (roslibpy) or ``{secs|sec, nsecs}`` (a ROS time)."""
    if isinstance(value, dict):
        value = value.get("secs", value.get("sec"))
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return int(value)


def granted(secret: str, msg: dict[str, Any], now: float | None = None) -> bool:
    """Whether an ``auth`` op is granted for ``secret``: rosauth's clock rule and MAC, compared in constant time."""
    now = time.time() if now is None else now
    t, end = _seconds(msg.get("t")), _seconds(msg.get("end"))
    fields = [msg.get(k) for k in ("mac", "client", "dest", "rand", "level")]
    if t is None or end is None or not all(isinstance(f, str) for f in fields):
        return False
    if abs(t - now) >= CLOCK_SLACK_S or end <= now:
        return False
    given, client, dest, rand, level = (str(f) for f in fields)
    return hmac.compare_digest(given, mac(secret, client, dest, rand, t, level, end))


def new_secret() -> str:
    """A fresh per-student secret."""
    return secrets.token_hex(32)


def read_secret(path: Path | str) -> str:
    """The secret in a secret file (its first line, stripped). Raises OSError when it cannot be read."""
    return Path(path).read_text(encoding="utf-8").strip()
