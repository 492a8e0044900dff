"""Home's side of the chair-wide Stop for goals (issue 38): this page's :class:`~pmk_nb.drive.StopWatch`.

While the preview has a chair link, the watch reads the chair's Stop latch (shared by every page's
kernel, keyed on the chair's resolved address): another page's Stop cancels this kernel's goals
(``ChairLink.stop_goals``, when it runs any) and every goal is refused while it holds (``ChairLink.goal_gate``). Home
greys "Set destination" and "Go to" meanwhile; the kernel refuses them anyway (a page can click a
disabled button).
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.drive import DriveClaim, StopWatch

if TYPE_CHECKING:
    from pmk_nb.chair.link import GoalLink

log = logging.getLogger(__name__)


class StopLatch:
    """The watch of the chair Home's preview shows; ``attach(link, topic)`` / ``attach(None)``."""

    def __init__(self, folder: Path, member: str) -> None:
        self.folder, self.member = folder, member
        self.watch: StopWatch | None = None
        self._link: GoalLink | None = None

    def attach(self, link: GoalLink | None, topic: str | None = None) -> None:
        """Watch ``link``'s chair (None: nothing; the previous link's gate opens again here)."""
        old, self.watch = self.watch, None
        if old is not None:
            old.close()
        if self._link is not None and getattr(self._link, "goal_gate", None) is not None:
            self._link.goal_gate = None
        self._link = link
        if link is None:
            return
        claim = DriveClaim(self.folder, link.host, link.port, member=self.member)
        self.watch = StopWatch(claim, lambda: on_latch(link, topic)).start()
        link.goal_gate = self.watch.latched_at

    @property
    def latched(self) -> bool:
        """A Stop holds for this chair (at the watch's latest read)."""
        watch = self.watch
        return watch is not None and watch.latched

    def close(self) -> None:
        self.attach(None)


def on_latch(link: GoalLink, topic: str | None) -> None:
    """Another page latched a Stop: this page's goals end the way its own Stop ends them. The page that
    pressed Stop has cancelled all goals natively already; this page adds its own goals' cancels (and,
    for them, a second native cancel-all), and stays quiet when it runs none (ten pages, one burst)."""
    if link.running_goals():
        link.stop_goals(topic)
