"""The TF tree view (issue 40) in Home's Plots panel: every frame as an indented tree, parent -> child,
its rate and the age of its last transform, as ``view_frames`` or RViz's TF display tell them.

While the panel is open a :class:`~pmk_nb.chair.link.TfWatch` hears ``/tf`` and ``/tf_static`` (its own
subscriptions, ended when the panel closes or the preview stops); the rows are the pure
:func:`~pmk_nb.viewport.tree_rows` and the text is refreshed from the panel's timer
(:meth:`TfTreeView.tick`), never per message.
"""

from __future__ import annotations

import ipywidgets as w

from pmk_nb.chair.link import LinkCore, TfWatch
from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.ui.common.widgets import escape
from pmk_nb.viewport import FrameRow, frame_text, tree_rows

#: seconds between text refreshes (the ages move on; a faster text only costs messages)
REFRESH_S = 0.5
TABLE_STYLE = "font-size: 12px; border-collapse: collapse"


class TfTreeView:
    """``widget``: a summary line and the frames' table; :meth:`attach` a link, :meth:`tick` from a timer."""

    def __init__(self, *, clock: Clock = MONOTONIC) -> None:
        self.clock = clock
        self.watch: TfWatch | None = None
        self.rows: list[FrameRow] = []
        self._shown_at = -float("inf")
        self.summary = w.HTML("")
        self.summary.add_class("pmk-tftree-summary")
        self.table = w.HTML("")
        self.table.add_class("pmk-tftree-table")
        self.widget = w.VBox([self.summary, self.table])
        self.widget.add_class("pmk-tftree")

    def attach(self, link: LinkCore | None) -> None:
        """Watch ``link``'s tf (None: the panel closed or the preview stopped; the subscriptions end)."""
        watch, self.watch = self.watch, None
        if watch is not None:
            watch.stop()
        self.rows = []
        self._shown_at = -float("inf")
        if link is None:
            self.summary.value = self.table.value = ""
            return
        if not link.is_connected:
            self.summary.value = "<span class='pmk-msg-warning'>Not connected to the chair.</span>"
            self.table.value = ""
            return
        self.watch = TfWatch(link.ros, link.ros_version, clock=self.clock)
        self.summary.value = "<small>Listening to /tf and /tf_static…</small>"
        self.table.value = ""

    def tick(self) -> None:
        """Refresh the rows and their text at most every :data:`REFRESH_S` seconds of the clock."""
        watch = self.watch
        now = self.clock.now()
        if watch is None or now - self._shown_at < REFRESH_S:
            return
        self._shown_at = now
        self.rows = tree_rows(watch.tree, now)
        if not self.rows:
            self.summary.value = "<small>No transforms yet on /tf or /tf_static.</small>"
            return
        roots = sum(1 for r in self.rows if r.depth == 0)
        self.summary.value = f"<small>{len(self.rows)} frames, {roots} tree{'s' if roots != 1 else ''}</small>"
        self.table.value = rows_html(self.rows)

    def close(self) -> None:
        self.attach(None)


def rows_html(rows: list[FrameRow]) -> str:
    """The frames as a table: the frame indented by its depth ("parent → child"), its rate and age."""
    lines = []
    for r in rows:
        pad = r.depth * 18
        name = escape(r.frame) if r.parent is None else f"{escape(r.parent)} → <b>{escape(r.frame)}</b>"
        lines.append(
            f"<tr class='pmk-tftree-row' data-frame='{escape(r.frame)}'>"
            f"<td style='padding-left:{pad}px'>{name}</td>"
            f"<td style='padding-left:12px'>{escape(frame_text(r))}</td></tr>"
        )
    return f"<table style='{TABLE_STYLE}'>{''.join(lines)}</table>"
