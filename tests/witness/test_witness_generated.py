"""A generator that knows the truth (issue 37): random buildings written as IndoorGML, converted, and the
written map compared with what was drawn; the witness must agree with that truth on every building.

Each building is a row of rooms south of a corridor: doors as thin door cells, as thick door slabs or
as bare shared walls; some neighbouring rooms joined by a transition of their own; an obstacle in a
room; 1.0 (State/Transition) or 2.0-draft (Node/Edge) encoding; plain or projected coordinates. The
truth is judged here with SciPy on the written image, from the boxes the generator drew, with no code
of the converter or of the witness.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy import ndimage

from pmk_nb.grid import FREE
from pmk_nb.library.convert import ConvertOptions, convert_plan
from pmk_nb.rosmap import read_map
from pmk_nb.witness import WitnessReport
from tests.access.test_access_rules import _cell, _graph, _plan

pytestmark = pytest.mark.slow  # each example converts a building

CHAIR = 0.7
Box = tuple[float, float, float, float]


@dataclass(frozen=True)
class Drawn:
    """What the generator drew: boxes by cell id, the graph's pairs, the obstacle, the offset."""

    boxes: dict[str, Box]
    rooms: list[str]
    pairs: list[tuple[str, str]]
    obstacle: str | None
    door_depth: float
    offset: tuple[float, float]


@st.composite
def buildings(draw: st.DrawFn) -> Drawn:
    n = draw(st.integers(2, 4))
    widths = [draw(st.sampled_from([3.0, 3.5, 4.0, 5.0, 6.0])) for _ in range(n)]
    depth = draw(st.sampled_from([3.5, 4.0, 5.0]))
    door_depth = draw(st.sampled_from([0.0, 0.2, 0.6]))
    corridor = draw(st.sampled_from([2.0, 2.5, 3.0]))
    offset = draw(st.sampled_from([(0.0, 0.0), (500_000.0, 5_400_000.0)]))
    ox, oy = offset
    boxes: dict[str, Box] = {}
    pairs: list[tuple[str, str]] = []
    rooms = []
    x = 0.0
    for i, w in enumerate(widths):
        room = f"R{i}"
        rooms.append(room)
        boxes[room] = (ox + x, oy, ox + x + w, oy + depth)
        if door_depth:
            at = x + draw(st.sampled_from([0.5, 1.0, w / 2 - 0.5, w - 1.7]))
            boxes[f"D{i}"] = (ox + at, oy + depth, ox + at + 1.2, oy + depth + door_depth)
            pairs += [(room, f"D{i}"), (f"D{i}", "COR")]
        else:
            pairs.append((room, "COR"))
        if i and draw(st.booleans()):
            pairs.append((rooms[i - 1], room))
        x += w
    top = depth + door_depth
    boxes["COR"] = (ox, oy + top, ox + x, oy + top + corridor)
    obstacle = None
    if draw(st.booleans()):
        x0, y0 = boxes["R0"][0], boxes["R0"][1]
        boxes["OBS"] = (x0 + 0.4, y0 + 0.4, x0 + 1.0, y0 + 1.0)
        obstacle = "OBS"
    return Drawn(boxes, rooms, pairs, obstacle, door_depth, offset)


def _write(tmp_path: Path, drawn: Drawn, v2: bool) -> Path:
    cells = ""
    for cid, box in drawn.boxes.items():
        tag = "CellSpace"
        if cid.startswith("D"):
            tag = "navi:ConnectionSpace"
        elif cid == "OBS":
            tag = "navi:NonNavigableSpace"
        elif cid.startswith("R"):
            tag = "navi:GeneralSpace"
        elif cid == "COR":
            tag = "navi:TransitionSpace"
        cells += _cell(cid, box, tag, name=cid)
    return _plan(tmp_path, cells, _graph(drawn.pairs, v2=v2), v2=v2)


class _Map:
    """The written map's free pixels, and boxes of the plan as pixel masks (in the map's frame)."""

    def __init__(self, yaml: Path, drawn: Drawn) -> None:
        grid = read_map(yaml)
        self.free = grid.data == FREE
        self.res = grid.resolution
        self.origin = grid.origin
        # the converter may read projected coordinates from a local origin: find the shift from a room
        self.shift = (0.0, 0.0)
        if drawn.offset != (0.0, 0.0):
            shift = grid.meta.get("crs_origin") or (0.0, 0.0)
            self.shift = (float(shift[0]), float(shift[1]))

    def box(self, b: Box, grow: float = 0.0) -> np.ndarray:
        h, w = self.free.shape
        xs = self.origin[0] + (np.arange(w) + 0.5) * self.res + self.shift[0]
        ys = self.origin[1] + (np.arange(h) + 0.5) * self.res + self.shift[1]
        c = (xs > b[0] - grow) & (xs < b[2] + grow)
        r = (ys > b[1] - grow) & (ys < b[3] + grow)
        return np.outer(r, c)

    def at(self, x: float, y: float) -> bool:
        c = int((x - self.shift[0] - self.origin[0]) / self.res)
        r = int((y - self.shift[1] - self.origin[1]) / self.res)
        return bool(self.free[r, c])


def _centre(b: Box) -> tuple[float, float]:
    return (b[0] + b[2]) / 2, (b[1] + b[3]) / 2


def _joined(m: _Map, room: np.ndarray, a: Box, b: Box, *, radius: float) -> bool:
    """Whether the centres of ``a`` and ``b`` are joined by free pixels inside ``room`` (for a disc)."""
    space = m.free & room
    if radius:
        space &= ndimage.distance_transform_edt(m.free) * m.res > radius
    labels, _ = ndimage.label(space, structure=np.ones((3, 3), bool))
    ends = []
    for box in (a, b):
        inside = m.box(box) & space
        ends.append(set(np.unique(labels[inside]).tolist()) - {0})
    return bool(ends[0] & ends[1])


def truth(m: _Map, drawn: Drawn) -> list[str]:
    """What is wrong in the written map, judged from the drawn boxes alone ([] for a right map)."""
    wrong = []
    bx = drawn.boxes
    for room in [*drawn.rooms, "COR"]:
        x1, y1 = bx[room][2:]
        if not m.at(x1 - 1.0, y1 - 0.8):
            wrong.append(f"{room} not free")
    if drawn.obstacle and m.at(*_centre(bx[drawn.obstacle])):
        wrong.append("obstacle free")
    for a, b in drawn.pairs:
        if a.startswith("D") or b.startswith("D"):
            continue  # judged with the door below, from room to corridor
        region = m.box(bx[a], 0.4) | m.box(bx[b], 0.4)
        if not _joined(m, region, bx[a], bx[b], radius=CHAIR / 2):
            wrong.append(f"{a}-{b} blocked")
    for i, room in enumerate(drawn.rooms):
        door = f"D{i}"
        if door in bx:
            region = m.box(bx[room]) | m.box(bx[door], 0.4) | m.box(bx["COR"])
            if not _joined(m, region, bx[room], bx["COR"], radius=CHAIR / 2):
                wrong.append(f"{room} cannot reach the corridor through {door}")
        if i and (drawn.rooms[i - 1], room) not in drawn.pairs:
            left = drawn.rooms[i - 1]
            region = (m.box(bx[left]) | m.box(bx[room]) | m.box(bx[room], 0.3)) & ~m.box(bx["COR"], 0.3)
            if _joined(m, region, bx[left], bx[room], radius=0.0):
                wrong.append(f"{left}-{room} leak")
    return wrong


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(drawn=buildings(), v2=st.booleans())
def test_the_witness_agrees_with_the_truth_on_generated_buildings(tmp_path: Path, drawn: Drawn, v2: bool) -> None:
    folder = Path(tempfile.mkdtemp(dir=tmp_path))  # hypothesis runs every example in one tmp_path
    plan = _write(folder, drawn, v2)
    result = convert_plan(plan, folder / "maps", "b", options=ConvertOptions(unit="m", chair_width=CHAIR))
    [written] = result.maps
    report: WitnessReport | None = written.witness
    assert report is not None
    wrong = truth(_Map(written.files.yaml, drawn), drawn)
    found = [f.describe() for f in report.findings]
    assert report.ok == (not wrong), f"truth: {wrong}; witness: {found}"
    assert not wrong, f"the converter drew a wrong map of a generated building: {wrong}"
