"""The TF tree view's rows (issue 40): parents, children, rates and ages from the receive times the tf
tree records, on a virtual clock, so the rates and ages are exact (quarter and eighth seconds are exact
binary fractions)."""

from __future__ import annotations

from dataclasses import dataclass

from pmk_nb.clock import VirtualClock
from pmk_nb.viewport import FrameRow, TfTree, frame_text, tree_rows


@dataclass(frozen=True)
class _T:
    parent: str
    child: str
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0


def _by_frame(rows: list[FrameRow]) -> dict[str, FrameRow]:
    return {r.frame: r for r in rows}


def _publish(tree: TfTree, clock: VirtualClock, seconds: float, *, odom: bool = True) -> None:
    """base_link in odom at 8 Hz and odom in map at 2 Hz, for ``seconds`` of the clock."""
    for _ in range(round(seconds / 0.125)):
        clock.advance(0.125)
        step = round((clock.now() - 1000.0) / 0.125)
        if odom:
            tree.set(_T("odom", "base_link"), clock.now())
        if step % 4 == 0:
            tree.set(_T("map", "odom"), clock.now())


def test_rates_ages_parents_and_children_are_exact_on_a_virtual_clock() -> None:
    clock = VirtualClock(start=1000.0)
    tree = TfTree()
    tree.set(_T("base_link", "laser", 0.2), clock.now(), static=True)
    _publish(tree, clock, 3.0)
    rows = tree_rows(tree, clock.now())
    assert [(r.frame, r.depth) for r in rows] == [("map", 0), ("odom", 1), ("base_link", 2), ("laser", 3)]
    by = _by_frame(rows)
    assert by["map"] == FrameRow("map", None, 0, False, None, None, ("odom",))
    assert by["odom"].parent == "map" and by["odom"].children == ("base_link",)
    assert by["odom"].rate_hz == 2.0 and by["odom"].age_s == 0.0  # 1000.5 ... 1003.0: 5 gaps in 2.5 s
    assert by["base_link"].rate_hz == 8.0 and by["base_link"].children == ("laser",)  # 23 gaps in 2.875 s
    assert by["laser"].static and by["laser"].rate_hz is None and by["laser"].age_s == 3.0
    assert frame_text(by["base_link"]) == "8.0 Hz · 0.00 s ago" and frame_text(by["map"]) == "root"
    assert frame_text(by["laser"]) == "static · 3.00 s ago"

    # base_link stops; odom goes on: base_link ages, its rate is over the window's arrivals only
    _publish(tree, clock, 3.0, odom=False)
    by = _by_frame(tree_rows(tree, clock.now()))
    assert by["base_link"].age_s == 3.0
    assert by["base_link"].rate_hz == 8.0  # 1001.0 ... 1003.0 in the 5 s window: 16 gaps in 2 s
    assert by["odom"].rate_hz == 2.0 and by["odom"].age_s == 0.0
    clock.advance(4.5)  # base_link's last arrival (1003.0) is 7.5 s old: none left in the window
    by = _by_frame(tree_rows(tree, clock.now()))
    assert by["base_link"].rate_hz is None and by["base_link"].age_s == 7.5
    assert frame_text(by["base_link"]) == "no rate · 7.50 s ago"
    assert by["odom"].rate_hz == 2.0 and by["odom"].age_s == 4.5  # 1005.5 and 1006.0 still in the window
    clock.advance(0.25)
    by = _by_frame(tree_rows(tree, clock.now()))
    assert by["odom"].rate_hz is None and by["odom"].age_s == 4.75  # one arrival left in it: no rate


def test_two_trees_and_a_cycle_are_all_listed() -> None:
    tree = TfTree()
    tree.set(_T("world", "a"), 1.0)
    tree.set(_T("other", "b"), 1.0)
    tree.set(_T("c", "d"), 1.0)
    tree.set(_T("d", "c"), 1.0)  # a misconfigured publisher: c <-> d
    rows = tree_rows(tree, 2.0)
    assert [(r.frame, r.depth) for r in rows] == [("other", 0), ("b", 1), ("world", 0), ("a", 1), ("c", 0), ("d", 1)]
    assert _by_frame(rows)["a"].age_s == 1.0
    tree.clear()
    assert tree_rows(tree, 2.0) == []
