"""Several chairs on one page (issue 26, Fleet): who is in the fleet, each chair's colour, which
one is in control, and the words of each chair's row. Pure: no link, no widget.

A lab watches several chairs at once but drives one: the page's Home, Drive and Go to act on the
chair *in control*; the others are watched (connection, map, pose, goal) and drawn as coloured
markers.  A chair's colour is chosen from its name (the same chair gets the same colour on every
page that opens the same fleet) and kept while it stays in the fleet: another chair leaving never
recolours it.  The palette avoids the live view's own colours (the chair's blue, the laser's red
and orange, the planned path's violet, the route's green, the stale chair's grey).
"""

from __future__ import annotations

import hashlib
import math
import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING

from pmk_nb.errors import PmkError

if TYPE_CHECKING:
    from pmk_nb.chair.profiles import ChairProfile

#: One colour per chair (CSS hex); after these, colours repeat (a fleet is capped at MAX_CHAIRS).
PALETTE: tuple[str, ...] = ("#e6007e", "#00a087", "#f0a000", "#8b4513", "#7cb518", "#00bcd4")
#: Chairs one page watches at once: each is a websocket, its streams and a worker thread.
MAX_CHAIRS = 8


class FleetError(PmkError):
    """Something the fleet cannot do (its subclasses say what)."""


class NotInFleet(FleetError):
    """``name`` is no chair of this fleet (a stale button, a page sending any value)."""

    def __init__(self, name: str) -> None:
        super().__init__(f"No chair called {name!r} is in the fleet.", hint="Add it first.")
        self.name = name


class FleetFull(FleetError):
    """The fleet holds ``max_chairs`` already."""

    def __init__(self, max_chairs: int) -> None:
        super().__init__(
            f"The fleet already watches {max_chairs} chairs, the most one page holds.",
            hint="Remove a chair before adding another.",
        )
        self.max_chairs = max_chairs


class SameAddress(FleetError):
    """Another chair of the fleet has this profile's address: one chair, one link (issue 40: it was left
    out without a word).

    Attributes:
        name: the profile not added; ``other``: the fleet's chair at that address; ``host``, ``port``.
    """

    def __init__(self, name: str, other: str, host: str, port: int) -> None:
        super().__init__(
            f"{name!r} is not added: {other!r} in the fleet is the same chair ({host}:{port}).",
            hint="Give each chair its own address in Settings.",
        )
        self.name, self.other, self.host, self.port = name, other, host, port


class NoChairChosen(FleetError):
    """Add was pressed with no chair picked in the list."""

    def __init__(self) -> None:
        super().__init__("Pick a saved chair in the list first.")


@dataclass(frozen=True)
class FleetMember:
    """One chair of the fleet: its profile (where it is, its topics and limits) and its colour."""

    profile: ChairProfile
    colour: str
    source: str = "profile"  # "profile": a saved chair profile; "class": a classroom seat's chair

    @property
    def name(self) -> str:
        return self.profile.name

    @property
    def key(self) -> tuple[str, int]:
        """The chair's address: the link registry's key (one link per chair per kernel)."""
        return (self.profile.host, int(self.profile.port))


def preferred_colour(name: str) -> int:
    """The palette index a chair called ``name`` prefers (a stable hash, not Python's salted one)."""
    return int.from_bytes(hashlib.sha256(name.encode("utf-8")).digest()[:4], "big") % len(PALETTE)


def pick_colour(name: str, taken: set[str]) -> str:
    """``name``'s preferred colour, else the next one not ``taken``, else the preferred one again."""
    start = preferred_colour(name)
    for step in range(len(PALETTE)):
        colour = PALETTE[(start + step) % len(PALETTE)]
        if colour not in taken:
            return colour
    return PALETTE[start]


class Fleet:
    """The chairs of one page and the one in control. Thread-safe (the panel's timer reads it).

    Args:
        max_chairs: the most chairs it holds.
    """

    def __init__(self, max_chairs: int = MAX_CHAIRS) -> None:
        self.max_chairs = int(max_chairs)
        self._lock = threading.Lock()
        self._members: dict[str, FleetMember] = {}
        self._controlled: str | None = None

    @property
    def members(self) -> list[FleetMember]:
        with self._lock:
            return list(self._members.values())

    @property
    def controlled(self) -> FleetMember | None:
        with self._lock:
            return self._members.get(self._controlled) if self._controlled is not None else None

    def get(self, name: str) -> FleetMember:
        """Raises NotInFleet."""
        with self._lock:
            member = self._members.get(name)
        if member is None:
            raise NotInFleet(name)
        return member

    def add(self, profile: ChairProfile, source: str = "profile") -> FleetMember:
        """Add a chair (the one already there when its name is in the fleet).

        Raises:
            SameAddress: another chair of the fleet has its host and port.
            FleetFull: ``max_chairs`` are in the fleet already.
        """
        key = (profile.host, int(profile.port))
        with self._lock:
            for member in self._members.values():
                if member.name == profile.name:
                    return member
                if member.key == key:
                    raise SameAddress(profile.name, member.name, *key)
            if len(self._members) >= self.max_chairs:
                raise FleetFull(self.max_chairs)
            member = FleetMember(profile, pick_colour(profile.name, {m.colour for m in self._members.values()}), source)
            self._members[profile.name] = member
            return member

    def remove(self, name: str) -> FleetMember:
        """Take a chair out (the chair in control too: then none is). Raises NotInFleet."""
        with self._lock:
            member = self._members.pop(name, None)
            if member is None:
                raise NotInFleet(name)
            if self._controlled == name:
                self._controlled = None
            return member

    def control(self, name: str) -> FleetMember:
        """Put ``name`` in control; returns it. Raises NotInFleet."""
        with self._lock:
            member = self._members.get(name)
            if member is None:
                raise NotInFleet(name)
            self._controlled = name
            return member


@dataclass(frozen=True)
class ChairStatus:
    """What a chair's row shows, read from its link at one moment.

    Attributes:
        connection: "connecting", "live", "stale", "unreachable" or "off".
        problem: why it is unreachable (the link error's own message), else None.
        map_name: the map the chair publishes (the PMK map server's answer), None: not known.
        pose: (x, y, yaw) in the map frame, None: none seen yet.
        goal: the goal's words ("moving, 3.2 m left"), None: no goal sent from this page.
        same_map: the chair is on the map the page shows (its marker is drawn).
    """

    name: str
    colour: str
    controlled: bool
    connection: str
    problem: str | None = None
    map_name: str | None = None
    pose: tuple[float, float, float] | None = None
    goal: str | None = None
    same_map: bool = True


CONNECTION_WORDS = {
    "connecting": "connecting…",
    "live": "live",
    "stale": "no data",
    "unreachable": "does not answer",
    "off": "not watched",
}


def pose_words(pose: tuple[float, float, float] | None) -> str:
    if pose is None or not all(math.isfinite(v) for v in pose):
        return "no position yet"
    x, y, yaw = pose
    return f"x {x:.2f} m, y {y:.2f} m, {math.degrees(yaw) % 360:.0f}°"


def row_words(status: ChairStatus) -> dict[str, str]:
    """The row's texts: connection, map, pose, goal (plain words; the panel escapes them)."""
    connection = CONNECTION_WORDS.get(status.connection, status.connection)
    if status.connection == "unreachable" and status.problem:
        connection = f"{connection}: {status.problem}"
    map_name = status.map_name or "map not known"
    if not status.same_map:
        map_name += " (another map: not drawn)"
    return {
        "connection": connection,
        "map": map_name,
        "pose": pose_words(status.pose),
        "goal": status.goal or "no goal",
    }
