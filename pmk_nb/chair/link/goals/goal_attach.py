"""Follow a Nav2 action's ``<action>/_action/status`` topic, to learn what became of our goal when
its ``action_result`` cannot reach us (the link dropped: the bridge sent it to a closed socket).

rosbridge does not tell a client the action's goal UUID, so ours is the first goal that shows up
as accepted/executing after we sent it (the status messages before the send name the goals that
are not ours). A second client sending a goal at the same instant could be mistaken for ours; a
chair has one dashboard. roslibpy re-subscribes the topic after a reconnect, and the topic keeps its
last message for late subscribers (transient local), so the goal's fate is known right after.
Callbacks run on roslibpy's I/O thread and only store.
"""

from __future__ import annotations

import threading
from typing import Any

import roslibpy

from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.wire import GOAL_STATUS_ARRAY, STATUS_ACCEPTED, STATUS_CANCELING, STATUS_EXECUTING

ACTIVE = (STATUS_ACCEPTED, STATUS_EXECUTING, STATUS_CANCELING)


class ActionStatusFollower:
    """The latest status code of our goal on one action (None: not seen, or no longer listed)."""

    def __init__(self, ros: roslibpy.Ros, action: str, *, clock: Clock = MONOTONIC) -> None:
        self._clock = clock  # the goal's: ``heard_at`` is compared with its watch's times
        self._lock = threading.Lock()
        self._known: set[tuple[int, ...]] = set()
        self._sent = False
        self.uuid: tuple[int, ...] | None = None
        self.code: int | None = None
        self.listed = False  # our goal is in the latest status message
        self.heard_at = 0.0  # the clock's time of the latest status message
        self._topic = roslibpy.Topic(ros, f"{action}/_action/status", GOAL_STATUS_ARRAY)
        self._topic.subscribe(self._on_status)

    def mark_sent(self) -> None:
        """Goals listed from now on that were not listed before may be ours."""
        with self._lock:
            self._sent = True

    def _on_status(self, msg: Any) -> None:  # I/O thread
        entries: dict[tuple[int, ...], int] = {}
        for entry in (msg or {}).get("status_list") or []:
            try:
                key = tuple(int(b) for b in entry["goal_info"]["goal_id"]["uuid"])
                entries[key] = int(entry["status"])
            except (KeyError, TypeError, ValueError):
                continue
        with self._lock:
            self.heard_at = self._clock.now()
            if self.uuid is None:
                if self._sent:
                    mine = [k for k, code in entries.items() if k not in self._known and code in ACTIVE]
                    self.uuid = mine[-1] if mine else None
                self._known |= set(entries)
            if self.uuid is not None:
                self.listed = self.uuid in entries
                self.code = entries.get(self.uuid, self.code)

    def close(self) -> None:
        try:
            self._topic.unsubscribe()
        except Exception:  # the socket may be gone; nothing to undo then
            pass
