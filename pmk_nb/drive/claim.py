"""One driver per chair, and a Stop that holds for every page: a small file all kernels share.

Each dashboard page has its own kernel (a separate process), so "who drives" and "Stop was
pressed" cannot live in a kernel. They live in one JSON file per chair (``address_port.json``, the
chair's resolved address: :mod:`pmk_nb.drive.chairkey`, so every spelling of one chair shares it) in a
folder every kernel of the dashboard sees (the settings folder's ``drive/``, mode 0700):

* ``pages``: every page with the drive panel open and its heartbeat (wall time, written at most
  once per :attr:`DriveClaim.beat_every`); a page silent for :attr:`DriveClaim.stale` seconds
  (crashed kernel, closed tab) counts as gone, so it never blocks driving for ever;
* ``owner``/``since``: the driving page; a live owner is taken over only by an explicit action
  (:meth:`DriveClaim.take_over`), which that page's session notices at its next tick (50 ms);
* ``stop_by``/``stop_at``: the chair-wide Stop latch. Any page's Stop sets it; every session checks
  it before each publish. Only the page that set it releases it (its next press, or its Release
  button), or, once that page is gone, an explicit release on another page. Time never clears it.

Why a file and not a topic on the chair: the file is on the machine that serves the pages, is
seen by the next tick of every kernel without a network round trip or a subscription to set up,
and a Stop is never lost to a dropped websocket. Pages of *another* dashboard (a second tablet with
its own server) do not see it; the chair's own watchdog and each page's Stop still apply there.

Writers take an ``flock`` on ``address_port.lock`` for their read-modify-write and replace the file
atomically (:func:`pmk_nb.fileio.atomic_write`); readers need no lock. The page's identity is the
kernel-side :attr:`DriveClaim.member`, never an id the page sends.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import uuid
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any

from pmk_nb.clock import WALL, Clock
from pmk_nb.drive.chairkey import chair_key
from pmk_nb.fileio import atomic_write

STALE_S = 3.0  # a page without a heartbeat for this long is gone
BEAT_EVERY_S = 1.0


class Hold(str, Enum):
    """What the shared state says about this page driving now."""

    FREE = "free"  # nobody drives (or the driver is gone), no Stop latched
    MINE = "mine"  # this page is the driver
    OTHER_DRIVER = "driven from another page"
    STOPPED_HERE = "stopped on this page"  # this page's Stop latch: its next press releases it
    STOPPED_ELSEWHERE = "stopped on another page"


@dataclass(frozen=True)
class ClaimView:
    """The shared state as this page sees it at ``now``."""

    hold: Hold
    owner_since: float | None = None  # wall time the current (live, other or mine) driver took over
    stop_at: float | None = None  # wall time of the latched Stop
    stop_by_me: bool = False
    setter_live: bool = False  # the page that latched the Stop is still open
    pages: int = 0  # live pages with the panel open

    @property
    def may_drive(self) -> bool:
        return self.hold in (Hold.FREE, Hold.MINE, Hold.STOPPED_HERE)


@dataclass
class _State:
    owner: str | None = None
    since: float | None = None
    stop_by: str | None = None
    stop_at: float | None = None
    pages: dict[str, float] = field(default_factory=dict)

    @classmethod
    def parse(cls, raw: Any) -> _State:
        """Anything unreadable is an empty state, except a Stop: a damaged file keeps a latch."""
        if not isinstance(raw, dict):
            return cls()
        pages = raw.get("pages")
        good = {
            k: float(v)
            for k, v in (pages.items() if isinstance(pages, dict) else ())
            if isinstance(k, str) and isinstance(v, (int, float)) and not isinstance(v, bool)
        }
        return cls(
            owner=raw["owner"] if isinstance(raw.get("owner"), str) else None,
            since=_num(raw.get("since")),
            stop_by=raw["stop_by"] if isinstance(raw.get("stop_by"), str) else None,
            stop_at=_num(raw.get("stop_at")),
            pages=good,
        )

    def dump(self) -> str:
        fields = ("owner", "since", "stop_by", "stop_at", "pages")
        return json.dumps({name: getattr(self, name) for name in fields})


def _num(value: Any) -> float | None:
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


class DriveClaim:
    """One page's handle on a chair's shared drive state (one per drive panel, i.e. per kernel).

    Args:
        folder: the shared folder (created 0700).
        host, port: the chair.
        member: this page's id (default: a fresh random one, so a page cannot pick another's).
        clock: wall seconds (all kernels on one machine share it): ``WALL``; a ``VirtualClock`` in tests.
    """

    def __init__(
        self,
        folder: str | Path,
        host: str,
        port: int,
        *,
        member: str | None = None,
        clock: Clock = WALL,
        stale: float = STALE_S,
        beat_every: float = BEAT_EVERY_S,
    ) -> None:
        self.folder = Path(folder)
        self.path = self.folder / f"{chair_key(host, port)}.json"
        self.member = member or uuid.uuid4().hex
        self.clock, self.stale, self.beat_every = clock, stale, beat_every
        self._beat_at: float | None = None

    # -- reading --------------------------------------------------------------------------------------
    def _read(self) -> _State:
        try:
            text = self.path.read_text(encoding="utf-8")
        except FileNotFoundError:
            return _State()
        try:
            return _State.parse(json.loads(text))
        except ValueError:
            return _State()

    def _live(self, state: _State, member: str | None, now: float) -> bool:
        beat = state.pages.get(member) if member is not None else None
        return beat is not None and now - beat <= self.stale

    def _view(self, state: _State, now: float) -> ClaimView:
        me = self.member
        owner_live = state.owner is not None and self._live(state, state.owner, now)
        stop_live = self._live(state, state.stop_by, now)
        live_pages = sum(1 for beat in state.pages.values() if now - beat <= self.stale)
        if state.stop_by is not None and state.stop_by != me:
            hold = Hold.STOPPED_ELSEWHERE
        elif owner_live and state.owner != me:
            hold = Hold.OTHER_DRIVER
        elif state.stop_by == me:
            hold = Hold.STOPPED_HERE
        else:
            hold = Hold.MINE if owner_live and state.owner == me else Hold.FREE
        return ClaimView(
            hold,
            owner_since=state.since if owner_live else None,
            stop_at=state.stop_at if state.stop_by is not None else None,
            stop_by_me=state.stop_by == me,
            setter_live=stop_live,
            pages=live_pages,
        )

    def view(self) -> ClaimView:
        """The shared state now; also this page's heartbeat, written at most once per ``beat_every``."""
        now = self.clock.now()
        if self._beat_at is None or now - self._beat_at >= self.beat_every or now < self._beat_at:
            return self._change(lambda _s, _n: None)
        return self._view(self._read(), now)

    def peek(self) -> ClaimView:
        """The shared state now, without this page's heartbeat (a watcher is not a driving page)."""
        return self._view(self._read(), self.clock.now())

    # -- writing --------------------------------------------------------------------------------------
    @contextlib.contextmanager
    def _locked(self) -> Iterator[None]:
        self.folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        with open(self.folder / f"{self.path.stem}.lock", "a+b") as lock:
            fcntl.flock(lock.fileno(), fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(lock.fileno(), fcntl.LOCK_UN)

    def _change(self, edit: Callable[[_State, float], None]) -> ClaimView:
        """Read, beat, ``edit``, drop gone pages, write; under the lock."""
        with self._locked():
            now = self.clock.now()
            state = self._read()
            state.pages[self.member] = now
            edit(state, now)
            state.pages = {k: v for k, v in state.pages.items() if now - v <= 10 * self.stale or k == state.stop_by}
            atomic_write(self.path, state.dump(), mode=0o600, durable=False)  # live state: no fsync before the zero
            self._beat_at = now
            return self._view(state, now)

    def acquire(self) -> ClaimView:
        """Become the driver if nobody (live) else is and no other page's Stop is latched."""

        def edit(state: _State, now: float) -> None:
            if self._view(state, now).hold is Hold.FREE:
                state.owner, state.since = self.member, now

        return self._change(edit)

    def take_over(self) -> ClaimView:
        """The explicit take-over: this page drives from now on, whoever drove (not past a Stop)."""

        def edit(state: _State, now: float) -> None:
            if state.owner != self.member:
                state.owner, state.since = self.member, now

        return self._change(edit)

    def stop(self) -> ClaimView:
        """Latch the chair-wide Stop (a later Stop of another page takes the latch over)."""

        def edit(state: _State, now: float) -> None:
            state.stop_by, state.stop_at = self.member, now

        return self._change(edit)

    def release_stop(self, *, force: bool = False) -> ClaimView:
        """Release this page's Stop; ``force`` (an explicit action) also a Stop whose page is gone."""

        def edit(state: _State, now: float) -> None:
            if state.stop_by == self.member or (force and not self._live(state, state.stop_by, now)):
                state.stop_by = state.stop_at = None

        return self._change(edit)

    def leave(self) -> None:
        """This page closes its panel: no longer the driver, no more heartbeat (a latch it set stays)."""

        def edit(state: _State, _now: float) -> None:
            if state.owner == self.member:
                state.owner = state.since = None
            if state.stop_by != self.member:
                state.pages.pop(self.member, None)
            else:  # its latch stays, and it counts as gone: another page may release it explicitly
                state.pages[self.member] = -1e18

        self._change(edit)
        self._beat_at = None
