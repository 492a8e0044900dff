"""Progress: the one shape every long operation reports in (convert, download, upload, deploy).

A :class:`Progress` names the step, how far it is (``None`` when unknown, e.g. a download without
a Content-Length) and a short human message. The CLI prints it, the dashboard moves a bar.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["Progress", "ProgressCallback", "emit", "sub_range"]


@dataclass(frozen=True)
class Progress:
    """One progress report.

    Attributes:
        step: what is being done, a short stable word ("read", "rasterise", "write", "upload", ...).
        fraction: 0..1 of the whole operation, or None when the total is unknown.
        message: a short text for a person ("storey F1", "120 / 480 KiB").
    """

    step: str
    fraction: float | None = None
    message: str = ""

    def __post_init__(self) -> None:
        if self.fraction is not None:
            object.__setattr__(self, "fraction", min(1.0, max(0.0, float(self.fraction))))


ProgressCallback = Callable[[Progress], None]


def emit(callback: ProgressCallback | None, step: str, fraction: float | None = None, message: str = "") -> None:
    """Call ``callback`` with a :class:`Progress` when there is one (saves every caller the None check)."""
    if callback is not None:
        callback(Progress(step, fraction, message))


def sub_range(callback: ProgressCallback | None, start: float, end: float) -> ProgressCallback | None:
    """A callback that maps a sub-operation's 0..1 onto ``start..end`` of the caller's operation."""
    if callback is None:
        return None
    span = end - start

    def scaled(p: Progress) -> None:
        callback(Progress(p.step, None if p.fraction is None else start + span * p.fraction, p.message))

    return scaled
