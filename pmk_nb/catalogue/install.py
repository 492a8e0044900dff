"""``pmk maps get`` and the Catalogue tab's Get: a building's files from a catalogue into the maps folder.

Every file is downloaded into a hidden staging folder inside the maps folder, its size and SHA-256
checked against the catalogue, the IndoorGML source checked to be IndoorGML and each map YAML to
name an image installed with it; only then are all files renamed into place in one go
(:func:`pmk_nb.fileio.replace_all`, the map YAMLs last). Any refusal leaves the maps folder as it was.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from pmk_nb.catalogue.hashes import file_sha256
from pmk_nb.catalogue.remote import Asset, Building, Catalogue, Reader, Storey
from pmk_nb.catalogue.state import InstallRecord
from pmk_nb.errors import (
    AlreadyExists,
    AssetMismatch,
    AssetOutsideCatalogue,
    AssetTooLarge,
    CatalogueError,
    DownloadTooLarge,
    MapLoadError,
)
from pmk_nb.fileio import replace_all
from pmk_nb.indoorgml import check_indoorgml
from pmk_nb.library import SOURCE_SUFFIXES, MapsFolder, check_name
from pmk_nb.progress import ProgressCallback, emit
from pmk_nb.rosmap import read_map_yaml

DEFAULT_MAX_BYTES = 200 * 1024 * 1024  # one file; a 100 M-cell map image is 100 MB
#: Asset keys installed, in rename order: the map YAML that names the others last.
INSTALLED = ("map-image", "preview", "rooms", "map-yaml")


@dataclass(frozen=True)
class InstallResult:
    name: str
    storeys: list[str]
    files: list[str]
    bytes: int


def install(
    catalogue: Catalogue,
    name: str,
    folder: MapsFolder,
    *,
    storeys: Sequence[str] = (),
    overwrite: bool = False,
    max_bytes: int = DEFAULT_MAX_BYTES,
    allow_hosts: Iterable[str] = (),
    progress: ProgressCallback | None = None,
) -> InstallResult:
    """Install building ``name`` (only ``storeys`` when given: names or map ids) into ``folder``.

    Raises:
        AssetMismatch, AssetOutsideCatalogue, AssetTooLarge, RedirectRefused: a file fails a check
            (nothing installed); AlreadyExists: a map of that name not installed from this catalogue
            and no ``overwrite``; CatalogueError / LibraryError: unknown building or storey, bad names.
    """
    building = catalogue.building(name)
    check_name(building.id)
    chosen = _choose(catalogue, building, storeys)
    assets = _assets(catalogue, building, chosen)
    for a in assets:
        if a.size > max_bytes:
            raise AssetTooLarge(url=a.url, asset=a.key, size=a.size, limit=max_bytes)
    record = InstallRecord(folder.root)
    rec = record.get(building.id)
    if not overwrite and folder.exists(building.id) and (rec is None or rec.get("catalogue") != catalogue.url):
        raise AlreadyExists(f"map {building.id!r} already exists; pass overwrite=True to replace it", name=building.id)
    reader = Reader(catalogue.url, allow_local=folder.allow_local, allow_hosts=allow_hosts)
    made = [p for p in (folder.root, *folder.root.parents) if not p.exists()]  # folders this install creates
    folder.root.mkdir(parents=True, exist_ok=True)
    stage = Path(tempfile.mkdtemp(prefix=".catalogue-", dir=folder.root))
    try:
        _install_files(catalogue, building, chosen, assets, folder, reader, rec, stage, progress)
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        for path in made:  # a refused install leaves no empty maps folder behind (issue 40)
            with contextlib.suppress(OSError):
                path.rmdir()  # only when empty
        raise
    shutil.rmtree(stage, ignore_errors=True)
    files = {a.file_name: a.sha256 for a in assets}

    everything = len(chosen) == len(building.storeys)
    same = rec is not None and rec.get("catalogue") == catalogue.url and isinstance(rec.get("files"), dict)
    same_rec = rec if same else None
    # --storey adds to what is there
    kept = {**same_rec["files"], **files} if same_rec is not None and not everything else files
    with contextlib.suppress(OSError):  # installed either way; the record only tells "new" from "changed"
        old_all = bool(same_rec is not None and same_rec.get("all_storeys"))
        record.put(building.id, catalogue.url, kept, all_storeys=everything or old_all)
    emit(progress, "done", 1.0, f"installed {building.id}")
    return InstallResult(building.id, [s.storey or s.id for s in chosen], list(files), sum(a.size for a in assets))


def _install_files(
    catalogue: Catalogue,
    building: Building,
    chosen: list[Storey],
    assets: list[Asset],
    folder: MapsFolder,
    reader: Reader,
    rec: dict[str, object] | None,
    stage: Path,
    progress: ProgressCallback | None,
) -> None:
    """Download every file into ``stage``, check them, swap them into the folder in one step."""
    try:
        total = sum(a.size for a in assets) or 1
        done = 0
        for a in assets:
            emit(progress, "download", done / total, f"{a.file_name} ({a.size} bytes)")
            _download(reader, a, stage / a.file_name)
            done += a.size
        _check_staged(building, assets, stage)
        replace_all(folder.root, [(a.file_name, stage / a.file_name) for a in assets])
        if rec is not None and rec.get("catalogue") == catalogue.url and len(chosen) == len(building.storeys):
            _remove_dropped(folder, building.id, rec, {a.file_name for a in assets})
    except OSError as err:
        raise CatalogueError(
            f"cannot install {building.id!r} in {folder.root}: {err.strerror or err}",
            url=catalogue.url,
            name=building.id,
        ) from err


def _remove_dropped(folder: MapsFolder, name: str, rec: dict[str, object], kept: set[str]) -> None:
    """Files the last install from this catalogue brought that it no longer lists (a storey dropped)."""
    files = rec.get("files")
    for old in files if isinstance(files, dict) else {}:
        path = folder.root / str(old)
        if old not in kept and path.parent == folder.root and str(old).startswith(f"{name}_") and path.is_file():
            path.unlink()


def _choose(catalogue: Catalogue, building: Building, wanted: Sequence[str]) -> list[Storey]:
    if not building.storeys:
        raise CatalogueError(f"{catalogue.url}: building {building.id!r} has no storey maps", url=catalogue.url)
    if not wanted:
        return list(building.storeys)
    chosen = [s for s in building.storeys if s.storey in wanted or s.id in wanted]
    missing = [w for w in wanted if not any(w in (s.storey, s.id) for s in building.storeys)]
    if missing:
        known = ", ".join(s.storey or s.id for s in building.storeys)
        raise CatalogueError(
            f"building {building.id!r} has no storey {missing[0]!r} (storeys: {known})",
            url=catalogue.url,
            name=building.id,
        )
    return chosen


def _assets(catalogue: Catalogue, building: Building, chosen: list[Storey]) -> list[Asset]:
    """The files to install, source first and map YAMLs last, each a plain name of this building."""
    source = building.source or next((s.assets["indoorgml"] for s in chosen if "indoorgml" in s.assets), None)
    picked = [source] if source is not None else []
    for key in INSTALLED:
        picked += [s.assets[key] for s in chosen if key in s.assets]
    if not any(a.key == "map-yaml" for a in picked):
        raise CatalogueError(f"building {building.id!r} lists no map YAML", url=catalogue.url, name=building.id)
    by_name: dict[str, Asset] = {}
    for a in picked:
        name = a.file_name
        stem_ok = name.startswith((f"{building.id}.", f"{building.id}_", f"{building.id}-"))
        if not stem_ok or name.startswith(".") or "/" in name or "\x00" in name or name != name.strip():
            raise AssetOutsideCatalogue(url=a.url, href=name, root=f"files named {building.id}*")
        if a.key == "indoorgml" and name[len(building.id) :].lower() not in SOURCE_SUFFIXES:
            raise AssetOutsideCatalogue(url=a.url, href=name, root=f"{building.id}.gml")
        if name in by_name and by_name[name].sha256 != a.sha256:
            raise CatalogueError(f"{a.url}: two different files named {name!r}", url=a.url, name=building.id)
        by_name.setdefault(name, a)
    return list(by_name.values())


def _download(reader: Reader, asset: Asset, target: Path) -> None:
    """Fetch one file (never more bytes than declared) and check its size and SHA-256."""
    with open(target, "wb") as out:
        try:
            reader.fetch_to(asset.url, out, max_bytes=asset.size)
        except DownloadTooLarge as err:
            raise AssetMismatch(
                url=asset.url, asset=asset.key, field="size", expected=asset.size, actual=err.size
            ) from err
    size = os.path.getsize(target)
    if size != asset.size:
        raise AssetMismatch(url=asset.url, asset=asset.key, field="size", expected=asset.size, actual=size)
    sha = file_sha256(target)
    if sha != asset.sha256:
        raise AssetMismatch(url=asset.url, asset=asset.key, field="checksum", expected=asset.sha256, actual=sha)


def _check_staged(building: Building, assets: list[Asset], stage: Path) -> None:
    """The source is IndoorGML; each map YAML names an image installed with it (a plain file name)."""
    names = {a.file_name for a in assets}
    for a in assets:
        if a.key == "indoorgml":
            check_indoorgml(stage / a.file_name, what=a.url, source="url")
        elif a.key == "map-yaml":
            try:
                image = read_map_yaml(stage / a.file_name).image_text  # the one YAML reader: a map server's rules
            except MapLoadError as err:
                raise CatalogueError(f"{a.url} is not a map YAML: {err}", url=a.url, name=building.id) from err
            if image not in names:
                raise AssetOutsideCatalogue(url=a.url, href=str(image), root="the files installed with it")
