"""Tiny IndoorGML documents built in code for the maps-folder tests (metres, 2D, IndoorGML 1.0.3).

Layout of :func:`two_rooms` per storey: room A is x 0..4, room B is x 4..8, both y 0..3; they share
the wall x = 4; a door cell D (x 3.9..4.1, y 1..2) connects them.
"""

from __future__ import annotations

_HEAD = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<core:IndoorFeatures xmlns:gml="http://www.opengis.net/gml/3.2" '
    'xmlns:xlink="http://www.w3.org/1999/xlink" '
    'xmlns:core="http://www.opengis.net/indoorgml/1.0/core" '
    'xmlns:navi="http://www.opengis.net/indoorgml/1.0/navigation" gml:id="IF">\n'
    '<core:primalSpaceFeatures><core:PrimalSpaceFeatures gml:id="PS">\n'
)
_TAIL = "</core:PrimalSpaceFeatures></core:primalSpaceFeatures>\n</core:IndoorFeatures>\n"


def _cell(cid: str, storey: str, box: tuple[float, float, float, float], tag: str = "core:CellSpace") -> str:
    x0, y0, x1, y1 = box
    ring = [(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)]
    pos = "".join(f"<gml:pos>{x} {y} 0.0</gml:pos>" for x, y in ring)
    return (
        f'<core:cellSpaceMember><{tag} gml:id="{cid}">'
        f'<gml:description>storey="{storey}":</gml:description><gml:name>{cid}</gml:name>'
        f'<core:cellSpaceGeometry><core:Geometry2D><gml:Polygon gml:id="G-{cid}"><gml:exterior>'
        f"<gml:LinearRing>{pos}</gml:LinearRing></gml:exterior></gml:Polygon></core:Geometry2D>"
        f"</core:cellSpaceGeometry></{tag}></core:cellSpaceMember>\n"
    )


def two_rooms(storeys: tuple[str, ...] = ("F1",), *, width: float = 8.0) -> bytes:
    """Two rooms and a door per storey; ``width`` stretches room B (to tell versions apart)."""
    body = []
    for s in storeys:
        body.append(_cell(f"A{s}", s, (0.0, 0.0, 4.0, 3.0), "navi:GeneralSpace"))
        body.append(_cell(f"B{s}", s, (4.0, 0.0, width, 3.0), "navi:GeneralSpace"))
        body.append(_cell(f"D{s}", s, (3.9, 1.0, 4.1, 2.0), "navi:ConnectionSpace"))
    return (_HEAD + "".join(body) + _TAIL).encode("utf-8")


HTML_PAGE = b"<!DOCTYPE html>\n<html><head><title>Not found</title></head><body><p>Sorry</p></body></html>\n"
BROKEN_HTML = b"<html><body><p>unclosed<br></body></html>"
ENTITY_BOMB = (
    b'<?xml version="1.0"?>\n<!DOCTYPE IndoorFeatures [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;">]>\n'
    b'<IndoorFeatures xmlns="http://www.opengis.net/indoorgml/1.0/core">&b;</IndoorFeatures>\n'
)
OTHER_XML = b'<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document/></kml>'
EXTERNAL_DTD = (
    b'<?xml version="1.0"?>\n<!DOCTYPE IndoorFeatures SYSTEM "file:///etc/passwd">\n'
    b'<IndoorFeatures xmlns="http://www.opengis.net/indoorgml/1.0/core"/>\n'
)
