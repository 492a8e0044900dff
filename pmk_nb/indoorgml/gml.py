"""GML 3.2 coordinate and geometry decoding, tolerant of what editors write in the wild.

``gml:pos`` / ``gml:posList`` with or without ``srsDimension`` (inferred from the token count or
from which reading closes the ring), ``gml:coordinates`` (with its ``cs``, ``ts`` and ``decimal``),
unclosed rings and repeated points. Surfaces are read wherever GML 3.2 puts them: Polygon, the patches
of Surface / PolyhedralSurface / TriangulatedSurface / Tin (PolygonPatch, Triangle, Rectangle), inside
MultiSurface, CompositeSurface, Shell, OrientableSurface (the orientation does not change a plan) and
Solid / CompositeSolid / MultiSolid, whose interior shells are voids (:attr:`PolygonZ.void`) when an exterior
shell holds them (a solid written with interior shells only is read from those). The
result is plain tuples; the footprint maths lives in :mod:`pmk_nb.indoorgml.footprint`.
"""

from __future__ import annotations

import functools
import math
import operator
from dataclasses import dataclass, field

from lxml import etree

from pmk_nb.errors import PmkError

GML_FAMILY = "opengis.net/gml"

Coord = tuple[float, ...]  # (x, y) or (x, y, z), file units


@dataclass
class RingStats:
    """Counts of repairs made while decoding, reported once per file instead of per ring."""

    unclosed: int = 0
    repeated: int = 0
    inferred_dim: int = 0
    interior_only: int = 0  # solids written with interior shells and no exterior: read as the solid


@dataclass(slots=True)
class PolygonZ:
    exterior: list[Coord]
    interiors: list[list[Coord]] = field(default_factory=list)
    void: int = 0  # > 0: a face of a solid's interior shell (a void, not space), numbered per shell


_SURFACES = frozenset(("polygon", "polygonpatch", "triangle", "rectangle"))
_LINES = frozenset(("linestring", "linestringsegment"))
_COORDS = frozenset(("pos", "poslist", "coordinates"))


class GmlTags:
    """The exact GML tags a document has used so far, by kind, so that lxml filters a feature's subtree
    in C instead of Python testing every element. A feature's elements all start before it ends, so the
    tags seen by then are all the tags it holds; names match as :func:`local` does (any case, any GML
    version's namespace)."""

    __slots__ = ("coords", "lines", "pos", "solids", "surfaces")

    def __init__(self) -> None:
        self.surfaces: tuple[str, ...] = ()
        self.lines: tuple[str, ...] = ()
        self.coords: tuple[str, ...] = ()
        self.pos: tuple[str, ...] = ()
        self.solids: tuple[str, ...] = ()  # gml:Solid: its interior shells are voids

    def note(self, tag: str) -> None:
        """Record one tag the first time the document uses it (the caller remembers which it has seen)."""
        if GML_FAMILY not in tag:
            return
        name = local_name(tag)
        if name in _SURFACES:
            self.surfaces += (tag,)
        elif name in _LINES:
            self.lines += (tag,)
        elif name in _COORDS:
            self.coords += (tag,)
            if name == "pos":
                self.pos += (tag,)
        elif name == "solid":
            self.solids += (tag,)


class CoordError(PmkError, ValueError):
    """A coordinate cannot be decoded; the caller adds file/cell context."""

    def __init__(self, msg: str, line: int | None) -> None:
        super().__init__(msg)
        self.line = line


def local(elem: etree._Element) -> str:
    """Lower-cased local name: matching is case-insensitive (``core:spaceLayer`` happens)."""
    tag = elem.tag
    return local_name(tag) if isinstance(tag, str) else ""


@functools.lru_cache(maxsize=1024)
def local_name(tag: str) -> str:
    """A file uses a few dozen tags a hundred thousand times: each is split once."""
    return tag.rpartition("}")[2].lower()


def is_gml(elem: etree._Element) -> bool:
    tag = elem.tag
    return isinstance(tag, str) and GML_FAMILY in tag


def _srs_dimension(elem: etree._Element) -> int | None:
    node: etree._Element | None = elem
    while node is not None:
        dim = node.get("srsDimension")
        if dim:
            try:
                value = int(dim)
            except ValueError:
                return None
            return value if value in (2, 3) else None
        node = node.getparent()
    return None


def _floats(text: str | None, elem: etree._Element) -> list[float]:
    tokens = (text or "").replace(",", " ").split()
    try:  # the common case in one pass; any doubt goes token by token for the message
        out = list(map(float, tokens))
        if math.isfinite(math.fsum(out)):
            return out
    except (ValueError, OverflowError):
        pass
    out = []
    for tok in tokens:
        try:
            v = float(tok)
        except ValueError:
            raise CoordError(f"bad coordinate {tok[:30]!r} in <gml:{_name(elem)}>", elem.sourceline) from None
        if not math.isfinite(v):
            raise CoordError(f"non-finite coordinate {tok!r} in <gml:{_name(elem)}>", elem.sourceline)
        out.append(v)
    return out


def _split(values: list[float], dim: int) -> list[Coord]:
    return list(zip(*[iter(values)] * dim, strict=False))  # whole tuples only: a trailing part is dropped


def _closes(points: list[Coord]) -> bool:
    return len(points) >= 2 and all(abs(a - b) < 1e-9 for a, b in zip(points[0], points[-1], strict=True))


def poslist_coords(
    elem: etree._Element, stats: RingStats, ring: bool, hint: int | None, values: list[float] | None = None
) -> list[Coord]:
    """Decode a posList (or the flat run of numbers ``values`` read from ``elem``) into points: the
    srsDimension here or on an ancestor, else ``count``, else the reading that fits (or closes the ring),
    else ``hint``."""
    if values is None:
        values = _floats(elem.text, elem)
    dim = _srs_dimension(elem)
    count = elem.get("count")
    if dim is None and count and count.isdigit() and int(count) > 0 and len(values) % int(count) == 0:
        dim = len(values) // int(count) if len(values) // int(count) in (2, 3) else None
    if dim is None:
        stats.inferred_dim += 1
        fits = [d for d in (2, 3) if len(values) % d == 0]
        if len(fits) == 1:
            dim = fits[0]
        elif ring and len(fits) == 2:
            closing = [d for d in fits if _closes(_split(values, d))]
            dim = closing[0] if len(closing) == 1 else (hint or 3)
        else:
            dim = hint or (fits[0] if fits else 2)
    if len(values) % dim:
        raise CoordError(
            f"<gml:{_name(elem)}> holds {len(values)} numbers, not a multiple of srsDimension={dim}",
            elem.sourceline,
        )
    return _split(values, dim)


def coordinates_coords(elem: etree._Element, stats: RingStats, ring: bool, hint: int | None) -> list[Coord]:
    """The deprecated gml:coordinates: tuples split by ``ts`` (default a space), numbers by ``cs`` (default a
    comma), ``decimal`` the decimal mark (default a point). Tuples that do not all hold 2 or 3 numbers
    ("1, 2 3, 4": a space after the comma) are read as one run of numbers, like a posList."""
    cs, ts, decimal = elem.get("cs") or ",", elem.get("ts") or " ", elem.get("decimal") or "."
    text = elem.text or ""
    tuples = text.split() if ts.isspace() else text.split(ts)
    rows = [[n for n in (t.split() if cs.isspace() else t.split(cs)) if n.strip()] for t in tuples]
    rows = [r for r in rows if r]
    numbers = [n.strip() for r in rows for n in r]
    values = _floats(" ".join(n.replace(decimal, ".") for n in numbers) if decimal != "." else " ".join(numbers), elem)
    dims = {len(r) for r in rows}
    if len(dims) == 1 and dims <= {2, 3} and len(values) == sum(map(len, rows)):
        return _split(values, dims.pop())
    return poslist_coords(elem, stats, ring, hint, values)


def pos_coord(elem: etree._Element) -> Coord:
    """A single gml:pos: the token count decides (srsDimension="3" with two numbers happens)."""
    values = _floats(elem.text, elem)
    if len(values) not in (2, 3):
        dim = _srs_dimension(elem)
        if dim and len(values) > dim:
            values = values[:dim]
        else:
            raise CoordError(f"<gml:pos> holds {len(values)} numbers (expected 2 or 3)", elem.sourceline)
    return tuple(values)


def coords_of(container: etree._Element, stats: RingStats, ring: bool, hint: int | None, tags: GmlTags) -> list[Coord]:
    """All coordinates under a LinearRing/LineString/Point, in document order."""
    pts: list[Coord] = []
    els = list(container.iter(*tags.coords)) if tags.coords else []
    if ring and hint is None and len(els) > 1 and local(els[0]) == "poslist":  # curve segments
        hint = _chained_dimension([e for e in els if local(e) == "poslist"])
    for el in els:
        name = local(el)
        if name == "pos":
            pts.append(pos_coord(el))
        elif name == "poslist":
            pts.extend(poslist_coords(el, stats, ring, hint))
        elif name == "coordinates":
            pts.extend(coordinates_coords(el, stats, ring, hint))
    return pts


def _chained_dimension(parts: list[etree._Element]) -> int | None:
    """The dimension (2 or 3) in which several posLists chain end to start into a closed ring (the
    segments of a gml:Ring), when no srsDimension says; None if not exactly one does."""
    runs = [_floats(e.text, e) for e in parts]
    fits = []
    for d in (2, 3):
        if all(len(v) % d == 0 and v for v in runs):
            segs = [_split(v, d) for v in runs]
            chained = all(a[-1] == b[0] for a, b in zip(segs, segs[1:] + segs[:1], strict=True))
            fits += [d] if chained else []
    return fits[0] if len(fits) == 1 else None


def clean_ring(points: list[Coord], stats: RingStats) -> list[Coord]:
    """Drop consecutive repeats and close the ring when the writer forgot to."""
    out: list[Coord] = []
    for p in points:
        if out and max(map(abs, map(operator.sub, out[-1], p)), default=0.0) < 1e-12:
            stats.repeated += 1
            continue
        out.append(p)
    if len(out) >= 3 and not _closes(out):
        stats.unclosed += 1
        out.append(out[0])
    return out


def _voids(root: etree._Element, tags: GmlTags, stats: RingStats) -> dict[etree._Element, int]:
    """The surfaces of the interior shells of the solids below ``root``, numbered by shell (from 1). The
    dict keeps the element proxies alive, so lxml hands out the same ones again in the walk that asks.

    An interior shell bounds a void *inside the exterior* (GML 3.2, SolidType): a solid with no exterior
    surfaces has nothing to hold a void, so its interior shells are the only geometry there is and are
    read as the solid itself (counted in ``stats.interior_only``), not dropped as voids."""
    out: dict[etree._Element, int] = {}
    shell = 0
    for solid in root.iter(*tags.solids):
        parts = [p for p in solid if is_gml(p)]
        inner = [p for p in parts if local(p) == "interior"]
        if not inner:
            continue
        if not any(local(p) == "exterior" and next(p.iter(*tags.surfaces), None) is not None for p in parts):
            stats.interior_only += 1
            continue
        for part in inner:
            shell += 1
            out.update((el, shell) for el in part.iter(*tags.surfaces))
    return out


def polygons_under(root: etree._Element, stats: RingStats, hint: int | None, tags: GmlTags) -> list[PolygonZ]:
    """Every gml:Polygon / PolygonPatch / Triangle / Rectangle below ``root`` (surfaces of solids included;
    those of a solid's interior shells marked as voids)."""
    out: list[PolygonZ] = []
    voids = _voids(root, tags, stats) if tags.solids else {}
    for el in root.iter(*tags.surfaces) if tags.surfaces else ():
        exterior: list[Coord] = []
        interiors: list[list[Coord]] = []
        for part in el:
            if not is_gml(part):
                continue
            which = local(part)
            if which in ("exterior", "outerboundaryis", "interior", "innerboundaryis"):
                ring = clean_ring(coords_of(part, stats, True, hint, tags), stats)
                if which in ("exterior", "outerboundaryis"):
                    exterior = ring
                elif len(ring) >= 4:
                    interiors.append(ring)
        void = voids.get(el, 0) if voids else 0
        if len(exterior) >= 4:
            out.append(PolygonZ(exterior, interiors, void))
        elif exterior:
            out.append(PolygonZ(exterior, [], void))  # degenerate: kept so the caller can report it
    return out


def lines_under(root: etree._Element, stats: RingStats, hint: int | None, tags: GmlTags) -> list[list[Coord]]:
    """Coordinates of every gml:LineString / Curve below ``root``."""
    out: list[list[Coord]] = []
    for el in root.iter(*tags.lines) if tags.lines else ():
        pts = coords_of(el, stats, False, hint, tags)
        if pts:
            out.append(pts)
    return out


def point_under(root: etree._Element, tags: GmlTags) -> Coord | None:
    for el in root.iter(*tags.pos) if tags.pos else ():
        return pos_coord(el)
    return None


def _name(elem: etree._Element) -> str:
    return etree.QName(elem).localname
