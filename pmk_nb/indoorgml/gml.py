"""GML 3.2 coordinate and geometry decoding, tolerant of what editors write in the wild.

``gml:pos`` / ``gml:posList`` with or without ``srsDimension`` (inferred from the token count or
from which reading closes the ring), ``gml:coordinates``, unclosed rings and repeated points. The
result is plain tuples; the footprint maths lives in :mod:`pmk_nb.indoorgml.footprint`.
"""

from __future__ import annotations

import functools
import math
import operator
from dataclasses import dataclass, field

from lxml import etree

GML_FAMILY = "opengis.net/gml"

Coord = tuple[float, ...]  # (x, y) or (x, y, z), file units


@dataclass
class RingStats:
    """Counts of repairs made while decoding, reported once per file instead of per ring."""

    unclosed: int = 0
    repeated: int = 0
    inferred_dim: int = 0


@dataclass(slots=True)
class PolygonZ:
    exterior: list[Coord]
    interiors: list[list[Coord]] = field(default_factory=list)


_SURFACES = frozenset(("polygon", "polygonpatch", "triangle"))
_LINES = frozenset(("linestring", "linestringsegment"))
_COORDS = frozenset(("pos", "poslist", "coordinates"))


class GmlTags:
    """The exact GML tags a document has used so far, by kind, so that lxml filters a feature's subtree
    in C instead of Python testing every element. A feature's elements all start before it ends, so the
    tags seen by then are all the tags it holds; names match as :func:`local` does (any case, any GML
    version's namespace)."""

    __slots__ = ("coords", "lines", "pos", "surfaces")

    def __init__(self) -> None:
        self.surfaces: tuple[str, ...] = ()
        self.lines: tuple[str, ...] = ()
        self.coords: tuple[str, ...] = ()
        self.pos: tuple[str, ...] = ()

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


class CoordError(ValueError):
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


def poslist_coords(elem: etree._Element, stats: RingStats, ring: bool, hint: int | None) -> list[Coord]:
    """Decode a posList; without srsDimension infer 2 or 3 from count / ring closure / hint."""
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
            f"<gml:posList> holds {len(values)} numbers, not a multiple of srsDimension={dim}",
            elem.sourceline,
        )
    return _split(values, dim)


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


def coords_of(
    container: etree._Element, stats: RingStats, ring: bool, hint: int | None, tags: GmlTags
) -> list[Coord]:  # fmt: skip
    """All coordinates under a LinearRing/LineString/Point, in document order."""
    pts: list[Coord] = []
    for el in container.iter(*tags.coords) if tags.coords else ():
        name = local_name(el.tag)
        if name == "pos":
            pts.append(pos_coord(el))
        elif name == "poslist":
            pts.extend(poslist_coords(el, stats, ring, hint))
        elif name == "coordinates":
            for tup in (el.text or "").split():
                pts.append(tuple(_floats(tup, el)))
    return pts


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


def polygons_under(root: etree._Element, stats: RingStats, hint: int | None, tags: GmlTags) -> list[PolygonZ]:
    """Every gml:Polygon / PolygonPatch / Triangle below ``root`` (surfaces of solids included)."""
    out: list[PolygonZ] = []
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
        if len(exterior) >= 4:
            out.append(PolygonZ(exterior, interiors))
        elif exterior:
            out.append(PolygonZ(exterior, []))  # degenerate: kept so the caller can report it
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
