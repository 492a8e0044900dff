"""Streaming scan of an IndoorGML document into raw records (file units, no interpretation yet).

Features (cells, boundaries, states, transitions, layers) are decoded when their end tag arrives
and then cleared, so memory stays proportional to one feature. Elements are matched by lower-cased
local name, whatever their prefix (``core:``, ``ns5:``, ``indoorCore:``, default namespace).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from lxml import etree

from pmk_nb.errors import IndoorGMLError
from pmk_nb.indoorgml import gml
from pmk_nb.indoorgml.drafts import draft_cell
from pmk_nb.indoorgml.gml import GML_FAMILY, CoordError, local, local_name
from pmk_nb.indoorgml.records import RawBoundary, RawCell, RawDocument, RawLayer, RawState, RawTransition
from pmk_nb.indoorgml.xmlsafe import GML_ID, iter_events
from pmk_nb.progress import ProgressCallback

XLINK_HREF = "{http://www.w3.org/1999/xlink}href"

CELL_NAMES = {
    "cellspace",
    "navigablespace",
    "generalspace",
    "transitionspace",
    "transferspace",
    "connectionspace",
    "anchorspace",
    "nonnavigablespace",
    "obstacle",
}
BOUNDARY_NAMES = {
    "cellspaceboundary",
    "navigableboundary",
    "connectionboundary",
    "anchorboundary",
    "transferboundary",
    "nonnavigableboundary",
}
STATE_NAMES = {"state", "node"}
TRANSITION_NAMES = {"transition", "edge"}
LAYER_NAMES = {"spacelayer", "primalspacelayer", "dualspacelayer", "thematiclayer"}
ROOT_NAMES = {"indoorfeatures", "multilayeredgraph", "primalspacefeatures", "indoorgml"}
GEOREF_NAMES = {"translation", "rotation", "lla", "lla_origin"}
_DECODED = frozenset(CELL_NAMES | BOUNDARY_NAMES | STATE_NAMES | TRANSITION_NAMES | LAYER_NAMES | GEOREF_NAMES)
_DECODED |= {"duality"}  # the 0.8/0.9 drafts write a cell as the State's duality itself (drafts.draft_cell)
_STOREY_TEXT = re.compile(r"\b(?:storey|story|level|floor)\s*[=:]\s*\"?([^\";:,\s]+)", re.IGNORECASE)


_XPOINTER = re.compile(r"""xpointer\(\s*(?:id\(\s*['"]([^'"]+)['"]\s*\)|.*@(?:gml:)?id\s*=\s*['"]([^'"]+)['"].*)\)""")


def href_id(ref: str | None) -> str | None:
    """The gml:id an ``xlink:href`` names, however it is spelled: ``#id``, ``id``, ``file.gml#id``,
    ``#xpointer(id('id'))`` or ``#xpointer(//*[@gml:id='id'])`` (GML 3.2 allows both shorthand and
    XPointer), with stray whitespace. The file part is dropped: every id is looked up in this file."""
    if not ref:
        return None
    tail = ref.strip().rsplit("#", 1)[-1].strip()
    m = _XPOINTER.fullmatch(tail)
    if m:
        tail = m.group(1) or m.group(2) or ""
    return tail or None


def _href(elem: etree._Element | None) -> str | None:
    """The id ``elem`` links to: its ``xlink:href`` (or an un-namespaced ``href``, as some exporters write)."""
    if elem is None:
        return None
    return href_id(elem.get(XLINK_HREF) or elem.get("href"))


def _child(elem: etree._Element, name: str) -> etree._Element | None:
    for c in elem:
        if local(c) == name:
            return c
    return None


def _kids(elem: etree._Element) -> dict[str, etree._Element]:
    """A feature's first child of each local name, in one pass (a feature asks for several)."""
    kids: dict[str, etree._Element] = {}
    for c in elem:
        kids.setdefault(local(c), c)
    return kids


def _text(elem: etree._Element | None) -> str:
    return " ".join((elem.text or "").split()) if elem is not None else ""


def _storey_like(name: str) -> bool:
    """A non-GML element that may name a cell's storey: IndoorGML 1.1/2.0 ``level`` or an extension."""
    return name == "level" or any(k in name for k in ("storey", "story", "floor"))


def _storey_of(elem: etree._Element, description: str, storey_tags: tuple[str, ...]) -> tuple[str | None, str]:
    """Storey from `level` (1.1/2.0), an extension element, or gml:description text.

    ``storey_tags``: the document's tags that :func:`_storey_like` accepts (lxml filters by them)."""
    for c in elem.iter(*storey_tags) if storey_tags else ():
        if c is elem:
            continue
        name = local(c)
        if name == "level" and _text(c):
            return _text(c), "level"
        if name != "level" and len(c) == 0 and _text(c):
            return _text(c), "extension"
    m = _STOREY_TEXT.search(description)
    if m:
        return m.group(1), "description"
    return None, ""


class _Scanner:
    def __init__(self, path: Path) -> None:
        self.doc = RawDocument(path=path, root="", namespaces={})
        # open elements: (local name, decoded at its end?, the element); its gml:id is read when asked for
        self.stack: list[tuple[str, bool, etree._Element]] = []
        self.names: dict[object, tuple[str, bool]] = {}  # tag -> (local name, decoded at its end?)
        self.tags = gml.GmlTags()
        self.storey_tags: tuple[str, ...] = ()

    def _ancestor(self, names: set[str]) -> tuple[str, str | None] | None:
        for name, _, elem in reversed(self.stack[:-1]):
            if name in names:
                return name, elem.get(GML_ID)
        return None

    def _layer(self) -> str:
        anc = self._ancestor(LAYER_NAMES)
        return (anc[1] or "") if anc else ""

    def _learn(self, tag: object) -> tuple[str, bool]:
        """Name a tag the first time the document uses it, and file it for the filtered walks."""
        name = local_name(tag) if isinstance(tag, str) else ""
        if isinstance(tag, str):
            self.tags.note(tag)
            if GML_FAMILY not in tag and _storey_like(name):
                self.storey_tags += (tag,)
        info = self.names[tag] = (name, name in _DECODED or name.endswith("member"))
        return info

    def start(self, elem: etree._Element) -> None:
        info = self.names.get(elem.tag) or self._learn(elem.tag)
        name = info[0]
        if not self.stack:
            self.doc.root = name
            self.doc.namespaces = {k or "": v for k, v in elem.nsmap.items()}
            if name not in ROOT_NAMES and not any("indoorgml" in v.lower() for v in elem.nsmap.values()):
                raise IndoorGMLError(
                    f"{self.doc.path}: not an IndoorGML document: the root element is "
                    f"<{etree.QName(elem).localname}> (expected IndoorFeatures or MultiLayeredGraph)",
                    path=str(self.doc.path),
                    element=etree.QName(elem).localname,
                )
        elif not self.doc.srs_name and elem.get("srsName"):
            self.doc.srs_name = elem.get("srsName")
        if name == "primalspacelayer":
            self.doc.has_primal_layer = True
        self.stack.append((name, info[1], elem))

    def end(self, elem: etree._Element) -> None:
        stack = self.stack
        name, decoded, _ = stack[-1]  # named at its start
        if not decoded and not (len(stack) > 1 and stack[-2][0] == "cellspacemember"):
            stack.pop()  # inside a feature (a coordinate, a ring): decoded with its feature
            return
        try:
            self._end(elem, name)
        except CoordError as err:
            ident = elem.get(GML_ID) or next((i for _, _, e in reversed(stack) if (i := e.get(GML_ID))), None)
            msg = f"{self.doc.path}: line {err.line}: {err} (in {ident or name!r})"
            raise IndoorGMLError(msg, path=str(self.doc.path), element=ident or name) from err
        stack.pop()

    def _end(self, elem: etree._Element, name: str) -> None:
        doc = self.doc
        consumed = True
        parent = elem.getparent()
        in_member = len(self.stack) > 1 and self.stack[-2][0] == "cellspacemember"
        if (name in CELL_NAMES or in_member) and not gml.is_gml(elem):
            self._cell(elem, name)
        elif name == "duality" and draft_cell(elem, self.stack[-2][0] if len(self.stack) > 1 else ""):
            self._cell(elem, "cellspace")  # the drafts have no cell types: every cell is a space
        elif name in BOUNDARY_NAMES and not gml.is_gml(elem):
            self._boundary(elem, name)
        elif name in STATE_NAMES and not gml.is_gml(elem):
            point_el = _child(elem, "geometry")
            point = gml.point_under(point_el, self.tags) if point_el is not None else None
            dual = _child(elem, "duality")
            cell = _href(dual)
            if cell is None and dual is not None and len(dual):
                cell = dual[0].get(GML_ID)
            doc.states.append(RawState(elem.get(GML_ID) or f"state{len(doc.states)}", point, cell, self._layer()))
        elif name in TRANSITION_NAMES and not gml.is_gml(elem):
            ends = [c for c in elem if local(c) in ("connects", "start", "end")]  # start/end: the 0.8/0.9 drafts
            connects = [h for h in map(_href, ends) if h]
            weight_el = _child(elem, "weight")
            try:
                weight = float(_text(weight_el)) if _text(weight_el) else None
            except ValueError:
                weight = None
            geom_el = _child(elem, "geometry")
            lines = gml.lines_under(geom_el, doc.stats, None, self.tags) if geom_el is not None else []
            doc.transitions.append(
                RawTransition(
                    elem.get(GML_ID) or "",
                    connects,
                    weight,
                    _href(_child(elem, "duality")),
                    self._layer(),
                    lines[0] if lines else None,
                )
            )
        elif name in LAYER_NAMES:
            self._layer_record(elem, name)
        elif name in GEOREF_NAMES and not gml.is_gml(elem):
            self._georef(elem, name)
        else:
            consumed = name.endswith("member") and not gml.is_gml(elem)
        if consumed:
            elem.clear(keep_tail=False)
            if parent is not None and name.endswith("member"):
                while elem.getprevious() is not None:
                    del parent[0]

    def _cell(self, elem: etree._Element, name: str) -> None:
        kids = _kids(elem)
        description = _text(kids.get("description"))
        storey, source = _storey_of(elem, description, self.storey_tags)
        if "level" in kids:
            self.doc.has_level = True
        refs: list[str] = []
        if "partialboundedby" in kids:
            bounded = [c for c in elem if local(c) == "partialboundedby"]
            refs = [h for h in map(_href, bounded) if h] + [c[0].get(GML_ID) or "" for c in bounded if len(c)]
        in_state = self._ancestor(STATE_NAMES)
        cell = RawCell(
            id=elem.get(GML_ID) or f"cell{len(self.doc.cells) + 1}",
            kind_name=name,
            name=_text(kids.get("name")),
            description=description,
            polygons=gml.polygons_under(elem, self.doc.stats, None, self.tags),
            line=elem.sourceline,
            layer=self._layer(),
            storey_hint=storey,
            storey_source=source,
            duality=_href(kids.get("duality")) or (in_state[1] if in_state else None),
            boundary_refs=[r for r in refs if r],
            wrapped="cellspacegeometry" in kids,
            alma_inline=in_state is not None,
        )
        self.doc.cells.append(cell)

    def _layer_record(self, elem: etree._Element, name: str) -> None:
        """A layer's words (1.x class/usage/function; 2.0 ThematicLayer theme) and the ThematicLayer it sits in."""
        kids = _kids(elem)
        if elem.get(GML_ID) is None and any(k in LAYER_NAMES for k in kids):
            return  # 2.0's property `primalSpaceLayer` around the feature `PrimalSpaceLayer`: same name lower-cased
        thematic = self._ancestor({"thematiclayer"})
        self.doc.layers.append(
            RawLayer(
                elem.get(GML_ID) or f"layer{len(self.doc.layers) + 1}",
                _text(kids.get("class")),
                _text(kids.get("usage")),
                _text(kids.get("function")),
                name=_text(kids.get("name")),
                kind_name=name,
                theme=_text(kids.get("theme")),
                semantic_extension=_text(kids.get("semanticextension")).lower() in ("true", "1"),
                parent=(thematic[1] or "") if thematic else "",
            )
        )

    def _boundary(self, elem: etree._Element, name: str) -> None:
        kids = _kids(elem)
        label, description = _text(kids.get("name")), _text(kids.get("description"))
        self.doc.boundaries.append(
            RawBoundary(
                id=elem.get(GML_ID) or f"boundary{len(self.doc.boundaries) + 1}",
                kind_name=name,
                name=label,
                description=description,
                polygons=gml.polygons_under(elem, self.doc.stats, None, self.tags),
                lines=gml.lines_under(elem, self.doc.stats, None, self.tags),
                duality=_href(kids.get("duality")),
                line=elem.sourceline,
                virtual=_says_virtual(elem, kids.get("isvirtual"), f"{label} {description}"),
            )
        )

    def _georef(self, elem: etree._Element, name: str) -> None:
        values = [float(v) for v in " ".join(elem.itertext()).replace(",", " ").split() if _is_number(v)]
        if name == "translation" and len(values) >= 2:
            self.doc.translation = (values[0], values[1])
        elif name == "rotation" and values:
            self.doc.rotation = values[0]
        elif name.startswith("lla") and len(values) >= 2:
            self.doc.lla = (values[0], values[1], values[2] if len(values) > 2 else 0.0)


def _says_virtual(elem: etree._Element, flag: etree._Element | None, words: str) -> bool:
    """IndoorGML 2.0's ``isVirtual`` (element ``flag`` or attribute), or ``words`` (its name and description)
    saying "virtual"."""
    if flag is not None and _text(flag).strip().lower() in ("true", "1"):
        return True
    if any(k.lower().endswith("isvirtual") and v.strip().lower() in ("true", "1") for k, v in elem.attrib.items()):
        return True
    return "virtual" in words.lower()


def _is_number(tok: str) -> bool:
    try:
        float(tok)
    except ValueError:
        return False
    return True


def scan(path: str | os.PathLike[str], progress: ProgressCallback | None = None) -> RawDocument:
    """Stream ``path`` once and return its raw records.

    Raises:
        IndoorGMLError: unreadable, unsafe, malformed or non-IndoorGML input (message names the file).
    """
    scanner = _Scanner(Path(path))
    for event, elem in iter_events(path, progress):
        if event == "start":
            scanner.start(elem)
        else:
            scanner.end(elem)
    if not scanner.doc.root:
        raise IndoorGMLError(f"{path}: no XML root element found", path=str(path))
    return scanner.doc
