"""``pmk maps publish``: the maps folder as a static STAC catalogue any web server can serve.

``SITE/catalog.json`` -> ``SITE/<building>/collection.json`` (the IndoorGML source beside it) ->
``SITE/<building>/<map>/<map>.json`` with the storey's map YAML, image, rooms file, preview and a
thumbnail. A file is written only when its bytes change (compared by SHA-256), and an Item keeps its
``datetime`` while its assets are unchanged: publishing again touches only what changed, so a
mirror (rsync, an object store sync) copies only that, and "changed since installed" stays true.
"""

from __future__ import annotations

import datetime as dt
import io
import shutil
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from urllib.parse import unquote

from pmk_nb.access import sidecar_path
from pmk_nb.catalogue import geo, stacdocs
from pmk_nb.catalogue.hashes import file_sha256, multihash
from pmk_nb.catalogue.state import read_json_object
from pmk_nb.errors import CatalogueError
from pmk_nb.fileio import atomic_write
from pmk_nb.library import GeneratedMap, MapEntry, MapsFolder

THUMBNAIL_PX = 256


@dataclass
class PublishResult:
    """What a publish did: ``written`` files changed, ``unchanged`` counts the others."""

    site: Path
    buildings: list[str]
    written: list[Path] = field(default_factory=list)
    unchanged: int = 0
    removed: list[Path] = field(default_factory=list)


class PlanMissing(CatalogueError):
    """Maps are in the folder but no building plan they belong to (`pmk convert --out MAPS` writes no plan):
    a catalogue publishes a building with its plan, so the plan is to be imported, not the maps converted.

    Attributes:
        maps: the map YAMLs without a plan (file names).
    """

    def __init__(self, root: Path, maps: Sequence[str], *, url: str) -> None:
        names = ", ".join(maps[:5]) + (f" and {len(maps) - 5} more" if len(maps) > 5 else "")
        super().__init__(
            f"nothing to publish: the maps in {root} ({names}) have no building plan there",
            url=url,
            hint="Import the plan they were converted from (pmk maps import PLAN.gml --name NAME, NAME being "
            "the maps' name before _<storey>), then publish again.",
        )
        self.maps = list(maps)


def publish(
    folder: MapsFolder,
    out: str | Path,
    names: Sequence[str] = (),
    *,
    title: str | None = None,
    now: dt.datetime | None = None,
) -> PublishResult:
    """Publish the converted maps ``names`` (default: every converted map) into the folder ``out``.

    Raises:
        PlanMissing: nothing to publish but maps without their plan (``pmk convert --out``).
        CatalogueError: a named map is not converted, has a broken map, or ``out`` cannot be written.
        LibraryError: an unknown map name.
    """
    site = Path(out).expanduser()
    entries = [folder.entry(n) for n in names] if names else [e for e in folder.list() if e.generated]
    if not entries:
        orphans = [g.yaml.name for g in folder.orphans()]
        if orphans:
            raise PlanMissing(folder.root, orphans, url=str(site))
        raise CatalogueError(f"nothing to publish: no converted map in {folder.root}", url=str(site))
    stamp = (now or dt.datetime.now(dt.UTC)).strftime("%Y-%m-%dT%H:%M:%SZ")
    old_catalog = read_json_object(site / "catalog.json")
    title = title or str(old_catalog.get("title") or "PMK maps")
    result = PublishResult(site=site, buildings=[e.name for e in entries])
    try:
        site.mkdir(parents=True, exist_ok=True)
        writer = _Writer(result)
        for entry in entries:
            _publish_building(folder, entry, site, title, stamp, writer)
        children = _children(old_catalog, site, [e.name for e in entries], keep_others=bool(names), result=result)
        writer.put(site / "catalog.json", stacdocs.dumps(stacdocs.catalog(title, children)).encode())
    except OSError as err:
        raise CatalogueError(f"cannot write the catalogue in {site}: {err.strerror or err}", url=str(site)) from err
    return result


class _Writer:
    """Writes a file only when its bytes differ from what is there (atomic, through fileio)."""

    def __init__(self, result: PublishResult) -> None:
        self.result = result

    def put(self, target: Path, content: bytes | Path) -> tuple[int, str]:
        """(size, hex SHA-256) of ``content`` now at ``target``."""
        if isinstance(content, Path):
            size, sha = content.stat().st_size, file_sha256(content)
        else:
            import hashlib

            size, sha = len(content), hashlib.sha256(content).hexdigest()
        if target.is_file() and target.stat().st_size == size and file_sha256(target) == sha:
            self.result.unchanged += 1
            return size, sha
        atomic_write(target, content, mkdir=True)
        self.result.written.append(target)
        return size, sha


def _publish_building(folder: MapsFolder, entry: MapEntry, site: Path, title: str, stamp: str, writer: _Writer) -> None:
    broken = [g.yaml.name for g in entry.generated if g.broken]
    if not entry.generated or broken:
        why = f"its maps {broken} cannot be read" if broken else "it is not converted yet"
        raise CatalogueError(
            f"cannot publish map {entry.name!r}: {why}",
            url=str(entry.source),
            name=entry.name,
            hint=f"Convert it first (pmk maps convert {entry.name}).",
        )
    bdir = site / entry.name
    source_name = f"{entry.name}{entry.source.suffix.lower()}"
    size, sha = writer.put(bdir / source_name, entry.source)
    source = stacdocs.asset("indoorgml", stacdocs.rel(".", source_name), size, multihash(sha))
    srs = geo.plan_srs(entry.source)
    extents = {s.name: geo.in_crs(s.extent, s.origin) for s in folder.storeys(entry.name)} if geo.utm_zone(srs) else {}
    old = read_json_object(bdir / "collection.json")
    items = []
    for gm in entry.generated:
        extent = extents.get(gm.storey or "") or (next(iter(extents.values())) if len(extents) == 1 else None)
        source_ref = {**source, "href": stacdocs.rel("..", source_name)}
        items.append(_publish_item(entry.name, gm, bdir, source_ref, geo.footprint(srs, extent), title, stamp, writer))
    _remove_gone_items(bdir, old, {i["id"] for i in items}, writer.result)
    doc = stacdocs.collection(entry.name, items, source, title)
    writer.put(bdir / "collection.json", stacdocs.dumps(doc).encode())


def _publish_item(
    building: str,
    gm: GeneratedMap,
    bdir: Path,
    source: dict[str, Any],
    geometry: dict[str, Any] | None,
    title: str,
    stamp: str,
    writer: _Writer,
) -> dict[str, Any]:
    item_id = gm.yaml.stem
    idir = bdir / item_id
    files: list[tuple[str, str, bytes | Path]] = [("map-yaml", gm.yaml.name, gm.yaml)]
    files.append(("map-image", gm.image.name, gm.image))
    rooms = sidecar_path(gm.yaml)
    if rooms.is_file():
        files.append(("rooms", rooms.name, rooms))
    if gm.preview is not None:
        files.append(("preview", gm.preview.name, gm.preview))
    files.append(("thumbnail", f"{item_id}.thumbnail.png", _thumbnail(gm.preview or gm.image)))
    assets = {"indoorgml": source}
    for key, name, content in files:
        size, sha = writer.put(idir / name, content)
        assets[key] = stacdocs.asset(key, stacdocs.rel(".", name), size, multihash(sha))
    old = read_json_object(idir / f"{item_id}.json")
    unchanged = old.get("assets") == assets and old.get("geometry") == geometry
    old_props = old.get("properties") or {}
    when = str(old_props["datetime"]) if unchanged and old_props.get("datetime") else stamp
    props = {
        "title": f"{building} {gm.storey}" if gm.storey else building,
        "datetime": when,
        "created": str(old_props.get("created") or when),
        "updated": when,
        "pmk:building": building,
        "pmk:storey": gm.storey,
        "pmk:resolution": gm.resolution,
        "pmk:width": gm.width,
        "pmk:height": gm.height,
    }
    doc = stacdocs.item(building, item_id, props, assets, geometry, geo.bbox_of(geometry), title)
    writer.put(idir / f"{item_id}.json", stacdocs.dumps(doc).encode())
    return doc


def _thumbnail(image: Path) -> bytes:
    """A PNG at most 256 px on a side (same input, same bytes: a re-publish leaves it alone)."""
    from PIL import Image

    with Image.open(image) as im:
        small = im.convert("RGB" if im.mode in ("RGB", "RGBA", "P") else "L")
        small.thumbnail((THUMBNAIL_PX, THUMBNAIL_PX))
        buf = io.BytesIO()
        small.save(buf, format="PNG")
    return buf.getvalue()


def _remove_gone_items(bdir: Path, old: dict[str, Any], keep: set[str], result: PublishResult) -> None:
    """Delete the folders of Items published before whose storey is gone (only plain child folders)."""
    for lk in old.get("links") or []:
        href = str(lk.get("href", "")) if isinstance(lk, dict) and lk.get("rel") == "item" else ""
        parts = [unquote(p) for p in href.split("/")]
        if len(parts) == 3 and parts[0] == "." and parts[1] not in keep and _plain(parts[1]):
            target = bdir / parts[1]
            if target.is_dir() and not target.is_symlink():
                shutil.rmtree(target)
                result.removed.append(target)


def _children(
    old_catalog: dict[str, Any], site: Path, published: list[str], *, keep_others: bool, result: PublishResult
) -> list[tuple[str, str]]:
    """The catalogue's buildings: those just published, plus (when only some were named) the others
    already there; publishing everything drops (and deletes) buildings no longer in the maps folder."""
    children = [(name, name) for name in published]
    for lk in old_catalog.get("links") or []:
        href = str(lk.get("href", "")) if isinstance(lk, dict) and lk.get("rel") == "child" else ""
        parts = [unquote(p) for p in href.split("/")]
        if len(parts) != 3 or parts[0] != "." or parts[2] != "collection.json" or not _plain(parts[1]):
            continue
        bid = parts[1]
        if bid in published or not (site / bid / "collection.json").is_file():
            continue
        if keep_others:
            children.append((bid, str(lk.get("title") or bid)))
        elif _ours(site / bid):
            shutil.rmtree(site / bid)
            result.removed.append(site / bid)
    return sorted(children, key=lambda c: c[0].casefold())


def _ours(folder: Path) -> bool:
    """A building folder this command published (its IndoorGML source listed): never another catalogue's."""
    return not folder.is_symlink() and "indoorgml" in (read_json_object(folder / "collection.json").get("assets") or {})


def _plain(name: str) -> bool:
    return bool(name) and name not in (".", "..") and not name.startswith(".") and "\\" not in name
