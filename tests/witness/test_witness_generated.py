"""A generator that knows the truth (issue 37): random buildings written as IndoorGML, converted, and the
written map compared with what was drawn; the witness must agree with that truth on every building.

Each building is a row of rooms south of a corridor: doors as thin door cells, as thick door slabs, or
bare shared walls with or without a door line (ConnectionBoundary); some neighbouring rooms joined by a
transition of their own; an obstacle in a room, in the floor's layer or in a layer of its own that the
graph does not link; an extra thematic layer (a zone); 2D polygons or 3D solids, one or two storeys;
metres, centimetres or millimetres (read by the converter's own unit vote, not given); plain or
projected coordinates; 1.0 (State/Transition) or 2.0-draft (Node/Edge) encoding; sometimes no graph at
all (then never "ok"), or a partial one (a room left out of it: its doors are doors, its walls walls).
The truth is judged here on the written image, from the boxes the generator drew, with no code of the
converter or of the witness (SciPy's distance transform and labelling).
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
from tests.access.test_access_rules import NS

pytestmark = pytest.mark.slow  # each example converts a building

CHAIR = 0.7
Box = tuple[float, float, float, float]


@dataclass(frozen=True)
class Drawn:
    """What the generator drew (metres, before the unit's scale): boxes by cell id, the graph's pairs,
    door lines, obstacles and the layer they are kept in, storeys, unit, encoding, offset."""

    boxes: dict[str, Box]
    rooms: list[str]
    pairs: list[tuple[str, str]]
    doors: dict[str, Box]  # door boundaries (lines, as degenerate boxes) in a bare shared wall, by room
    obstacle: str | None
    obstacle_layer: bool  # the obstacle kept in a layer of its own that the graph does not link
    zone: bool  # an extra thematic layer: a zone over the rooms, neither floor nor obstacle
    door_depth: float
    offset: tuple[float, float]
    storeys: int  # > 1: 3D solids one above the other
    solid: bool
    scale: float  # file units per metre: 1 (m), 100 (cm), 1000 (mm)
    graph: bool  # False: the file has no navigation graph at all
    unlinked: str | None = None  # a partial graph: this room has no state, so no transition


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
    doors: dict[str, Box] = {}
    pairs: list[tuple[str, str]] = []
    rooms = []
    x = 0.0
    for i, w in enumerate(widths):
        room = f"R{i}"
        rooms.append(room)
        boxes[room] = (ox + x, oy, ox + x + w, oy + depth)
        at = x + draw(st.sampled_from([0.5, 1.0, w / 2 - 0.5, w - 1.7]))
        if door_depth:
            boxes[f"D{i}"] = (ox + at, oy + depth, ox + at + 1.2, oy + depth + door_depth)
            pairs += [(room, f"D{i}"), (f"D{i}", "COR")]
        else:
            pairs.append((room, "COR"))
            if draw(st.booleans()):
                doors[room] = (ox + at, oy + depth, ox + at + 1.0, oy + depth)
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
    storeys = draw(st.sampled_from([1, 1, 2]))
    unlinked = draw(st.sampled_from([None, None, None, *rooms]))  # a partial graph: one room left out
    if unlinked is not None:
        pairs = [p for p in pairs if unlinked not in p]
    return Drawn(
        boxes,
        rooms,
        pairs,
        doors,
        obstacle,
        obstacle_layer=obstacle is not None and draw(st.booleans()),
        zone=draw(st.booleans()),
        door_depth=door_depth,
        offset=offset,
        storeys=storeys,
        solid=storeys > 1 or draw(st.booleans()),
        scale=draw(st.sampled_from([1.0, 1.0, 100.0, 1000.0])),
        graph=draw(st.sampled_from([True, True, True, False])),
        unlinked=unlinked,
    )


TAGS = {
    "D": "navi:ConnectionSpace",
    "R": "navi:GeneralSpace",
    "C": "navi:TransitionSpace",
    "O": "navi:NonNavigableSpace",
}
STOREY_H = 3.5  # metres from floor to floor; cells 3 m high


def _num(v: float, scale: float) -> str:
    return f"{v * scale:.4f}"


def _geometry(box: Box, z0: float, drawn: Drawn) -> str:
    s = drawn.scale
    pts = [(box[0], box[1]), (box[2], box[1]), (box[2], box[3]), (box[0], box[3]), (box[0], box[1])]
    if not drawn.solid:
        ring = " ".join(f"{_num(x, s)} {_num(y, s)}" for x, y in pts)
        return (
            f"<Geometry2D><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList>{ring}</gml:posList>"
            f"</gml:LinearRing></gml:exterior></gml:Polygon></Geometry2D>"
        )
    faces = ""
    for z in (z0, z0 + 3.0):
        ring = " ".join(f"{_num(x, s)} {_num(y, s)} {_num(z, s)}" for x, y in pts)
        faces += (
            f"<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension='3'>"
            f"{ring}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></gml:surfaceMember>"
        )
    return (
        f"<Geometry3D><gml:Solid><gml:exterior><gml:Shell>{faces}</gml:Shell></gml:exterior></gml:Solid></Geometry3D>"
    )


def _cells(drawn: Drawn, ids: list[str], k: int) -> str:
    out = ""
    for cid in ids:
        tag = "CellSpace" if cid == "ZONE" else TAGS[cid[0]]
        box = drawn.boxes[cid] if cid != "ZONE" else _zone(drawn)
        desc = "" if drawn.solid else f'<gml:description>storey="F{k}":</gml:description>'
        out += (
            f'<cellSpaceMember><{tag} gml:id="{cid}_{k}">{desc}<gml:name>{cid}_{k}</gml:name><cellSpaceGeometry>'
            f"{_geometry(box, k * STOREY_H, drawn)}</cellSpaceGeometry></{tag}></cellSpaceMember>"
        )
    return out


def _zone(drawn: Drawn) -> Box:
    r = drawn.boxes[drawn.rooms[-1]]
    return (r[0] + 0.5, r[1] + 0.5, r[2] - 0.5, r[3] - 0.5)


def _door_lines(drawn: Drawn, k: int) -> str:
    out = ""
    for room, b in drawn.doors.items():
        pts = f"{_num(b[0], drawn.scale)} {_num(b[1], drawn.scale)} {_num(b[2], drawn.scale)} {_num(b[3], drawn.scale)}"
        out += (
            f'<cellSpaceBoundaryMember><navi:ConnectionBoundary gml:id="B{room}_{k}"><cellSpaceBoundaryGeometry>'
            f"<geometry2D><gml:LineString><gml:posList>{pts}</gml:posList></gml:LineString></geometry2D>"
            f"</cellSpaceBoundaryGeometry></navi:ConnectionBoundary></cellSpaceBoundaryMember>"
        )
    return out


def _layer_xml(layer: str, cells: list[str], pairs: list[tuple[str, str]], v2: bool) -> str:
    state, trans = ("Node", "Edge") if v2 else ("State", "Transition")
    nodes = "".join(
        f'<{state.lower()}Member><{state} gml:id="S{c}"><duality xlink:href="#{c}"/></{state}></{state.lower()}Member>'
        for c in cells
    )
    edges = "".join(
        f'<{trans.lower()}Member><{trans} gml:id="T{layer}{i}"><connects xlink:href="#S{a}"/>'
        f'<connects xlink:href="#S{b}"/></{trans}></{trans.lower()}Member>'
        for i, (a, b) in enumerate(pairs)
    )
    if v2:
        return f'<dualSpaceLayer><DualSpaceLayer gml:id="D{layer}">{nodes}{edges}</DualSpaceLayer></dualSpaceLayer>'
    return (
        f'<spaceLayerMember><SpaceLayer gml:id="{layer}"><nodes gml:id="N{layer}">{nodes}</nodes>'
        f'<edges gml:id="E{layer}">{edges}</edges></SpaceLayer></spaceLayerMember>'
    )


def _write(folder: Path, drawn: Drawn, v2: bool) -> Path:
    """The building as IndoorGML: the floor in one layer with its graph; the obstacle (when kept apart)
    and the zone in a second layer the graph does not link; one copy of the layout per storey."""
    floor_ids = [c for c in drawn.boxes if c != "OBS" or not drawn.obstacle_layer]
    other_ids = (["OBS"] if drawn.obstacle_layer else []) + (["ZONE"] if drawn.zone else [])
    floor = other = lines = ""
    floor_states: list[str] = []
    other_states: list[str] = []
    pairs: list[tuple[str, str]] = []
    for k in range(drawn.storeys):
        floor += _cells(drawn, floor_ids, k)
        other += _cells(drawn, other_ids, k)
        lines += _door_lines(drawn, k)
        floor_states += [f"{c}_{k}" for c in floor_ids if c != drawn.unlinked]
        other_states += [f"{c}_{k}" for c in other_ids]
        pairs += [(f"{a}_{k}", f"{b}_{k}") for a, b in drawn.pairs]
    if not drawn.graph:
        pairs = []
    layers = _layer_xml("P", floor_states, pairs, v2) + (_layer_xml("X", other_states, [], v2) if other_ids else "")
    if v2:
        body = (
            f'<primalSpaceFeatures><PrimalSpaceLayer gml:id="P">{floor}{lines}</PrimalSpaceLayer></primalSpaceFeatures>'
        )
        if other_ids:
            body += (
                f'<primalSpaceFeatures><PrimalSpaceLayer gml:id="X">{other}</PrimalSpaceLayer></primalSpaceFeatures>'
            )
        body += layers
    else:
        body = (
            f'<primalSpaceFeatures><PrimalSpaceFeatures gml:id="F1">{floor}{other}{lines}</PrimalSpaceFeatures>'
            f'</primalSpaceFeatures><multiLayeredGraph><MultiLayeredGraph gml:id="G"><spaceLayers gml:id="L">'
            f"{layers}</spaceLayers></MultiLayeredGraph></multiLayeredGraph>"
        )
    path = folder / ("v2.gml" if v2 else "v1.gml")
    path.write_text(f'<?xml version="1.0"?><IndoorFeatures {NS} gml:id="F">{body}</IndoorFeatures>')
    return path


class _Map:
    """The written map's free pixels, and boxes of the plan as pixel masks (in the map's frame)."""

    def __init__(self, yaml: Path, drawn: Drawn) -> None:
        grid = read_map(yaml)
        self.free = grid.data == FREE
        self.res = grid.resolution
        self.origin = grid.origin
        # projected coordinates are read from a local origin, kept in the YAML (metres of the CRS)
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
        if room == drawn.unlinked:
            # a room the graph is silent about: its doors (a door cell, a door line) are doors, as in a
            # plan without a graph; with neither, its walls stay shut
            region = m.box(bx[room]) | m.box(bx[room], 0.4) | m.box(bx["COR"])
            if door not in bx and room not in drawn.doors and _joined(m, region, bx[room], bx["COR"], radius=0.0):
                wrong.append(f"{room}, in no transition and with no door, leaks into the corridor")
        elif door in bx:
            region = m.box(bx[room]) | m.box(bx[door], 0.4) | m.box(bx["COR"])
            if not _joined(m, region, bx[room], bx["COR"], radius=CHAIR / 2):
                wrong.append(f"{room} cannot reach the corridor through {door}")
        if i and (drawn.rooms[i - 1], room) not in drawn.pairs:
            left = drawn.rooms[i - 1]
            region = (m.box(bx[left]) | m.box(bx[room]) | m.box(bx[room], 0.3)) & ~m.box(bx["COR"], 0.3)
            if _joined(m, region, bx[left], bx[room], radius=0.0):
                wrong.append(f"{left}-{room} leak")
    return wrong


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(drawn=buildings(), v2=st.booleans())
def test_the_witness_agrees_with_the_truth_on_generated_buildings(tmp_path: Path, drawn: Drawn, v2: bool) -> None:
    folder = Path(tempfile.mkdtemp(dir=tmp_path))  # hypothesis runs every example in one tmp_path
    plan = _write(folder, drawn, v2)
    result = convert_plan(plan, folder / "maps", "b", options=ConvertOptions(chair_width=CHAIR))
    assert result.building.unit == {1.0: "m", 100.0: "cm", 1000.0: "mm"}[drawn.scale], result.building.unit_reason
    assert len(result.maps) == drawn.storeys
    for written in result.maps:
        report: WitnessReport | None = written.witness
        assert report is not None
        found = [f.describe() for f in report.findings]
        wrong = truth(_Map(written.files.yaml, drawn), drawn)
        if not drawn.graph:  # nothing to judge the map against: never "ok", and no alarm about the floor
            assert (report.ok, report.graph, found) == (False, False, []), found
            continue
        assert report.ok == (not wrong), f"storey {written.storey}: truth: {wrong}; witness: {found}"
        assert not wrong, f"the converter drew a wrong map of a generated building: {wrong}"
