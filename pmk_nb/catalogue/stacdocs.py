"""The STAC documents of a maps catalogue as plain dicts: one Catalog, a Collection per building,
an Item per storey (STAC 1.1.0, file extension 2.1.0 for ``file:size`` / ``file:checksum``).

Every link is relative, so the folder can be copied anywhere (a "self-contained" catalogue: no
``self`` links). Extra facts a map server needs are the ``pmk:`` fields of an Item's properties.
"""

from __future__ import annotations

import json
from typing import Any
from urllib.parse import quote

STAC_VERSION = "1.1.0"
FILE_EXTENSION = "https://stac-extensions.github.io/file/v2.1.0/schema.json"
JSON = "application/json"
GEOJSON = "application/geo+json"
WORLD = [-180.0, -90.0, 180.0, 90.0]

#: What each asset key holds: (title, roles). Installed: every key but the thumbnail.
ASSET_KINDS: dict[str, tuple[str, list[str]]] = {
    "indoorgml": ("IndoorGML building plan (the source)", ["data", "source"]),
    "map-yaml": ("map_server YAML", ["data", "metadata"]),
    "map-image": ("map_server image (occupancy)", ["data"]),
    "rooms": ("rooms and wheelchair access (NAME.rooms.json)", ["metadata"]),
    "preview": ("preview image", ["overview"]),
    "thumbnail": ("thumbnail", ["thumbnail"]),
}
MEDIA_TYPES = {
    ".gml": "application/gml+xml",
    ".xml": "application/xml",
    ".yaml": "application/yaml",
    ".pgm": "image/x-portable-graymap",
    ".png": "image/png",
    ".json": JSON,
}


def rel(*parts: str) -> str:
    """A relative href from path parts (``"."`` or ``".."`` first), each part percent-encoded: map
    names may hold spaces, which a URI may not."""
    return "/".join(p if p in (".", "..") else quote(p) for p in parts)


def dumps(doc: dict[str, Any]) -> str:
    """The one serialisation (stable key order as built, two-space indent): equal docs, equal bytes."""
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def link(rel: str, href: str, *, media: str = JSON, title: str | None = None) -> dict[str, str]:
    out = {"rel": rel, "href": href, "type": media}
    if title:
        out["title"] = title
    return out


def asset(key: str, href: str, size: int, checksum: str) -> dict[str, Any]:
    title, roles = ASSET_KINDS[key]
    media = MEDIA_TYPES.get("." + href.rsplit(".", 1)[-1].lower(), "application/octet-stream")
    return {"href": href, "type": media, "title": title, "roles": roles, "file:size": size, "file:checksum": checksum}


def catalog(title: str, children: list[tuple[str, str]]) -> dict[str, Any]:
    """The root: ``children`` are (building id, title)."""
    links = [link("root", "./catalog.json", title=title)]
    links += [link("child", rel(".", bid, "collection.json"), title=btitle) for bid, btitle in children]
    return {
        "type": "Catalog",
        "stac_version": STAC_VERSION,
        "id": "pmk-maps",
        "title": title,
        "description": f"{title}: building plans (IndoorGML) and wheelchair maps (ROS map_server) published by pmk_nb",
        "links": links,
    }


def collection(
    building: str, items: list[dict[str, Any]], source: dict[str, Any], catalog_title: str
) -> dict[str, Any]:
    """A building: its storeys' Items, the IndoorGML source as a Collection asset."""
    boxes = [i["bbox"] for i in items if i.get("bbox")] or [WORLD]
    bbox = [min(b[0] for b in boxes), min(b[1] for b in boxes), max(b[2] for b in boxes), max(b[3] for b in boxes)]
    times = sorted(i["properties"]["datetime"] for i in items) or [None]
    links = [link("root", "../catalog.json", title=catalog_title), link("parent", "../catalog.json")]
    links += [
        link("item", rel(".", i["id"], f"{i['id']}.json"), media=GEOJSON, title=i["properties"]["title"]) for i in items
    ]
    return {
        "type": "Collection",
        "stac_version": STAC_VERSION,
        "stac_extensions": [FILE_EXTENSION],
        "id": building,
        "title": building,
        "description": f"Building {building}: {len(items)} storey map(s) for the PMK wheelchair",
        "license": "other",
        "extent": {"spatial": {"bbox": [bbox]}, "temporal": {"interval": [[times[0], times[-1]]]}},
        "links": links,
        "assets": {"indoorgml": source},
    }


def item(
    building: str,
    item_id: str,
    props: dict[str, Any],
    assets: dict[str, dict[str, Any]],
    geometry: dict[str, Any] | None,
    bbox: list[float] | None,
    catalog_title: str,
) -> dict[str, Any]:
    doc: dict[str, Any] = {
        "type": "Feature",
        "stac_version": STAC_VERSION,
        "stac_extensions": [FILE_EXTENSION],
        "id": item_id,
        "geometry": geometry,
    }
    if bbox is not None:
        doc["bbox"] = bbox
    doc.update(
        properties=props,
        links=[
            link("root", "../../catalog.json", title=catalog_title),
            link("parent", "../collection.json", title=building),
            link("collection", "../collection.json", title=building),
        ],
        assets=assets,
        collection=building,
    )
    return doc
