"""The TF tree view's maths (issue 40): per frame its parent, rate, age and children, as
``view_frames`` or RViz's TF display tell them, from the receive times the :class:`TfTree` records.

Pure: ``now`` is passed in (the caller's clock, the one that stamped the arrivals), so a test on a
virtual clock asserts exact rates and ages. The rate is the mean over the transforms received in the
last ``window_s`` seconds ((n - 1) / their span, as ``view_frames`` averages its buffer); a frame
silent for the whole window has no rate, only its age.
"""

from __future__ import annotations

from dataclasses import dataclass

from pmk_nb.viewport.tftree import EdgeRecord, TfTree

#: seconds of arrivals the rate is averaged over
RATE_WINDOW_S = 5.0


@dataclass(frozen=True)
class FrameRow:
    """One frame of the tree, in depth-first order: ``depth`` 0 for a root (a frame with no parent).

    ``rate_hz`` is None for a static frame, a root, or fewer than two transforms in the window;
    ``age_s`` (seconds since its last transform) is None for a root.
    """

    frame: str
    parent: str | None
    depth: int
    static: bool
    rate_hz: float | None
    age_s: float | None
    children: tuple[str, ...]


def edge_rate(arrivals: tuple[float, ...], now: float, window_s: float = RATE_WINDOW_S) -> float | None:
    """Transforms per second over the arrivals within ``window_s`` of ``now`` (None: fewer than two)."""
    recent = [t for t in arrivals if now - window_s <= t <= now]
    if len(recent) < 2 or recent[-1] <= recent[0]:
        return None
    return (len(recent) - 1) / (recent[-1] - recent[0])


def frame_rows(edges: dict[str, EdgeRecord], now: float, window_s: float = RATE_WINDOW_S) -> list[FrameRow]:
    """The tree depth first from its roots, children by name; a cycle's frames are listed once, as roots."""
    children: dict[str, list[str]] = {}
    for child, edge in edges.items():
        children.setdefault(edge.parent, []).append(child)
    frames = set(edges) | set(children)
    roots = sorted(f for f in frames if f not in edges)
    rows: list[FrameRow] = []
    seen: set[str] = set()

    def visit(frame: str, depth: int) -> None:
        if frame in seen:
            return
        seen.add(frame)
        kids = tuple(sorted(children.get(frame, ())))
        edge = edges.get(frame)
        if edge is None or depth == 0:
            rows.append(FrameRow(frame, None if edge is None else edge.parent, depth, False, None, None, kids))
        else:
            age = now - edge.arrivals[-1] if edge.arrivals else None
            rate = None if edge.static else edge_rate(edge.arrivals, now, window_s)
            rows.append(FrameRow(frame, edge.parent, depth, edge.static, rate, age, kids))
        for kid in kids:
            visit(kid, depth + 1)

    for root in roots:
        visit(root, 0)
    for frame in sorted(frames - seen):  # only in a cycle (a misconfigured publisher): still shown
        visit(frame, 0)
    return rows


def tree_rows(tree: TfTree, now: float, window_s: float = RATE_WINDOW_S) -> list[FrameRow]:
    """:func:`frame_rows` of ``tree`` now."""
    return frame_rows(tree.edges(), now, window_s)


def frame_text(row: FrameRow) -> str:
    """One row in words: "static", "10.0 Hz · 0.05 s ago", "1 transform · 3.0 s ago", "root"."""
    if row.parent is None:
        return "root"
    age = "" if row.age_s is None else f" · {row.age_s:.2f} s ago"
    if row.static:
        return f"static{age}"
    if row.rate_hz is None:
        return f"no rate{age}"
    return f"{row.rate_hz:.1f} Hz{age}"
