"""The phrase queue: what to say next, without repeating or chattering.

Rules (all times from an injectable clock, seconds):

* the same text is not said again within ``repeat_after`` (a second tap on Go, a link that flaps);
* a phrase with the same key as one still waiting replaces it (connection lost, then regained
  before it was said: only "restored" is said; the newest goal news wins);
* at most ``max_waiting`` phrases wait; the oldest is dropped (stale news is worse than none);
* phrases come out at least ``min_gap`` apart, so one is not cut off by the next.

Thread-safe: the link's watchdog thread and widget callbacks both add phrases; the UI takes them.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True)
class Phrase:
    key: str
    text: str
    added: float


class PhraseQueue:
    def __init__(
        self,
        *,
        repeat_after: float = 5.0,
        min_gap: float = 0.8,
        max_waiting: int = 4,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.repeat_after, self.min_gap, self.max_waiting = repeat_after, min_gap, max_waiting
        self._clock = clock
        self._waiting: list[Phrase] = []
        self._said: dict[str, float] = {}  # text -> when it was last taken
        self._last_out = -float("inf")
        self._lock = threading.Lock()
        self.enabled = True

    def say(self, key: str, text: str) -> bool:
        """Queue ``text``; False when it is dropped (disabled, said just now, or already waiting)."""
        now = self._clock()
        with self._lock:
            if not self.enabled or not text:
                return False
            if now - self._said.get(text, -float("inf")) < self.repeat_after:
                return False
            if any(p.text == text for p in self._waiting):
                return False
            self._waiting = [p for p in self._waiting if p.key != key]
            self._waiting.append(Phrase(key, text, now))
            del self._waiting[: max(0, len(self._waiting) - self.max_waiting)]
            return True

    def add(self, phrase: tuple[str, str]) -> bool:
        """``say(*phrase)`` for the ``(key, text)`` pairs of :mod:`pmk_nb.speech.phrases`."""
        return self.say(*phrase)

    def take(self) -> Phrase | None:
        """The next phrase to say now, or None (nothing waiting, or too soon after the last one)."""
        now = self._clock()
        with self._lock:
            if not self._waiting or now - self._last_out < self.min_gap:
                return None
            phrase = self._waiting.pop(0)
            self._last_out = now
            self._said[phrase.text] = now
            self._said = {t: at for t, at in self._said.items() if now - at < self.repeat_after}
            return phrase

    def clear(self) -> None:
        with self._lock:
            self._waiting.clear()

    @property
    def waiting(self) -> list[str]:
        with self._lock:
            return [p.text for p in self._waiting]
