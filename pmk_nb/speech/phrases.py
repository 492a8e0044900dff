"""The sentences the chair says: short, in the same words every time, naming the room.

Each function returns ``(key, text)``: the key groups phrases about one thing (the link, the goal)
so that :class:`pmk_nb.speech.queue.PhraseQueue` lets a newer one replace an older one not yet said.
"""

from __future__ import annotations

from collections.abc import Sequence

GOAL = "goal"
LINK = "link"
STOP = "stop"
HERE = "here"

#: Why the chair stopped (the values of :class:`pmk_nb.drive.gate.StopReason`, and "cancel" for a
#: cancelled goal), in words; a reason not listed is just "Stopped.", and ``SILENT`` ones say nothing
STOP_REASONS = {
    "released": "",  # the deadman: the stick was let go
    "stop button": "",
    "page hidden": "page hidden",
    "no news from the page": "connection too slow",
    "link stale": "no data from the chair",
    "cancel": "goal cancelled",
}
SILENT_STOPS = frozenset({"closed"})  # the page or the preview closed: nobody to tell


def destination_set(room: str) -> tuple[str, str]:
    return GOAL, f"Going to {room}."


def arrived(room: str) -> tuple[str, str]:
    return GOAL, f"Arrived at {room}."


def route_blocked(room: str, doors: Sequence[str] = ()) -> tuple[str, str]:
    """No accessible route; the too-narrow doors are named (at most two, to stay short)."""
    if not doors:
        return GOAL, f"No accessible route to {room}."
    named = " and ".join(doors[:2])
    verb = "is" if len(doors[:2]) == 1 else "are"
    return GOAL, f"No accessible route to {room}. {named} {verb} too narrow."


def goal_failed(room: str) -> tuple[str, str]:
    return GOAL, f"Could not reach {room}."


def connection_lost() -> tuple[str, str]:
    return LINK, "Connection to the chair lost."


def connection_regained() -> tuple[str, str]:
    return LINK, "Connection to the chair restored."


def stopped(reason: str = "") -> tuple[str, str]:
    why = STOP_REASONS.get(reason, "")
    return STOP, f"Stopped, {why}." if why else "Stopped."


def you_are_in(room: str) -> tuple[str, str]:
    return HERE, f"You are in {room}."
