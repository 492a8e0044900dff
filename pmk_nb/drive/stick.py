"""One joystick message from the page, validated, and how old it is in the kernel's clock.

The page sends JSON ``{"page", "seq", "press", "t", "x", "y", "held", "hidden"}``: ``page`` names
one page load, ``seq`` counts its messages, ``press`` counts its presses (a Stop or a safety stop
ends a press; only a new press drives again), ``t`` is the page's ``performance.now()`` in ms.
Anything else, or anything out of range, is refused: a page (or anyone on its websocket) can send
any JSON, and this one moves a wheelchair.

The two clocks are not synchronised. The smallest ``kernel_time - page_time`` seen so far is the
offset plus the fastest delivery, so ``page_time + offset`` is the latest a message can have been
sent: its age is never overestimated by more than the fastest delivery, never underestimated
(except by the clock drift allowance, :data:`DRIFT`).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any

from pmk_nb.errors import PmkError

MAX_MESSAGE_CHARS = 512
#: How fast the offset may grow (s per s) without a new lower sample: two quartz clocks drift
#: apart by far less than 1e-4 (100 ppm); a page clock that runs slow makes ages look larger
#: (commands dropped, the safe side) until this catches up.
DRIFT = 1e-4
_FIELDS = {"page": str, "seq": int, "press": int, "t": float, "x": float, "y": float, "held": bool, "hidden": bool}


class StickMessageError(PmkError):
    """A joystick message that is not what the dashboard's page sends; nothing moves.

    Attributes:
        field: the offending key (None when the message is not a JSON object at all).
    """

    def __init__(self, message: str, *, field: str | None = None) -> None:
        super().__init__(message)
        self.field = field


@dataclass(frozen=True)
class StickEvent:
    """A stick position (unit disc, ``y`` forward, ``x`` right) at page time ``t`` (seconds)."""

    page: str
    seq: int
    press: int
    t: float
    x: float
    y: float
    held: bool
    hidden: bool = False


def _field(raw: dict[str, Any], name: str, kind: type) -> Any:
    value = raw[name]
    if kind is bool:
        if not isinstance(value, bool):
            raise StickMessageError(f"{name}: expected true or false, got {value!r}", field=name)
        return value
    accepted = (int, float) if kind is float else (kind,)
    if isinstance(value, bool) or not isinstance(value, accepted):
        raise StickMessageError(f"{name}: expected a {kind.__name__}, got {value!r}", field=name)
    if kind is float and isinstance(value, int):
        try:  # JSON integers are unbounded: 10**400 fits 512 characters but no float
            return float(value)
        except OverflowError:
            raise StickMessageError(f"{name}: a number out of range", field=name) from None
    return value


def parse_stick_message(text: object) -> StickEvent:
    """Validate one message from the page.

    Raises:
        StickMessageError: not JSON, not an object, a key missing or unknown, a value of the wrong
            type or out of range (``x``/``y`` in [-1.5, 1.5], then pulled onto the unit disc).
    """
    if not isinstance(text, str) or len(text) > MAX_MESSAGE_CHARS:
        raise StickMessageError(f"a joystick message is text of at most {MAX_MESSAGE_CHARS} characters")
    try:
        raw = json.loads(text)
    except ValueError as err:
        raise StickMessageError(f"a joystick message is JSON: {err}") from None
    if not isinstance(raw, dict):
        raise StickMessageError(f"a joystick message is a JSON object, got {type(raw).__name__}")
    unknown, missing = sorted(set(raw) - set(_FIELDS)), sorted(set(_FIELDS) - set(raw))
    if unknown or missing:
        name = (unknown or missing)[0]
        raise StickMessageError(f"{name}: {'unknown' if unknown else 'missing'} key", field=name)
    values = {name: _field(raw, name, kind) for name, kind in _FIELDS.items()}
    if not 0 < len(values["page"]) <= 64:
        raise StickMessageError("page: 1 to 64 characters", field="page")
    for name in ("seq", "press"):
        if not 0 <= values[name] < 2**53:
            raise StickMessageError(f"{name}: a count from 0, got {values[name]!r}", field=name)
    if not (math.isfinite(values["t"]) and values["t"] >= 0):
        raise StickMessageError(f"t: milliseconds since the page loaded, got {values['t']!r}", field="t")
    for name in ("x", "y"):
        if not (math.isfinite(values[name]) and abs(values[name]) <= 1.5):
            raise StickMessageError(f"{name}: a stick position in [-1, 1], got {values[name]!r}", field=name)
    x, y = float(values["x"]), float(values["y"])
    r = math.hypot(x, y)
    if r > 1.0:
        x, y = x / r, y / r
    return StickEvent(
        values["page"], values["seq"], values["press"], values["t"] / 1000.0, x, y, values["held"], values["hidden"]
    )


class ClockOffset:
    """Page time -> kernel time, from the smallest ``kernel_time - page_time`` observed."""

    def __init__(self) -> None:
        self._offset: float | None = None
        self._at = 0.0

    @property
    def known(self) -> bool:
        return self._offset is not None

    def reset(self) -> None:
        """A new page (a reload starts its own clock)."""
        self._offset = None

    def observe(self, kernel_now: float, page_t: float) -> None:
        sample = kernel_now - page_t
        if self._offset is None:
            self._offset = sample
        else:
            allowed = self._offset + DRIFT * max(0.0, kernel_now - self._at)
            self._offset = min(allowed, sample)
        self._at = kernel_now

    def kernel_time(self, page_t: float) -> float:
        """When (kernel clock) a message stamped ``page_t`` was sent, at the latest."""
        if self._offset is None:
            raise ValueError("no message observed yet: the offset is unknown")
        return page_t + self._offset
