"""The maps folder (the original app's ALMA_MAPS): IndoorGML sources and the maps generated from them.

Layout, as in the original (thesis 3.2.2): ``NAME.gml`` is the source; converting it writes
``NAME.yaml`` + ``NAME.pgm`` + ``NAME-visualization.png`` for a one-storey building, or
``NAME_<storey>.yaml`` ... per storey. Every write is atomic (temp file in the folder + rename) and a
failed download, import or conversion leaves the folder as it was.
"""

from __future__ import annotations

import builtins
import contextlib
import hashlib
import os
import shutil
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO

from pmk_nb.access import sidecar_path
from pmk_nb.defaults import DEFAULT_CHAIR_WIDTH, DEFAULT_DOOR_WIDTH, DEFAULT_MAX_WALL_GAP, DEFAULT_WALL_THICKNESS
from pmk_nb.errors import (
    AlreadyExists,
    IndoorGMLError,
    LibraryError,
    MapFormatError,
    MapsFolderMissing,
    OccupancyError,
)
from pmk_nb.fileio import atomic_write
from pmk_nb.indoorgml import check_indoorgml
from pmk_nb.library.convert import ConvertOptions, convert_plan
from pmk_nb.library.download import DEFAULT_DEADLINE, DEFAULT_MAX_BYTES, DEFAULT_TIMEOUT, check_url, fetch
from pmk_nb.library.info import StoreyCache, StoreyInfo
from pmk_nb.library.naming import SOURCE_SUFFIXES, check_name
from pmk_nb.library.netguard import ALLOW_LOCAL_ENV
from pmk_nb.library.scan import GeneratedMap, scan_generated
from pmk_nb.progress import ProgressCallback

__all__ = ["GeneratedMap", "MapEntry", "MapsFolder", "StoreyInfo", "check_name", "default_maps_dir"]


def default_maps_dir() -> Path:
    """The maps folder: ``$PMK_MAPS_DIR`` if set, else ``<user data dir>/pmk_nb/ALMA_MAPS``; created here."""
    env = os.environ.get("PMK_MAPS_DIR", "").strip()
    if env:
        path = Path(env).expanduser()
    else:
        import platformdirs

        path = Path(platformdirs.user_data_dir("pmk_nb")) / "ALMA_MAPS"
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise LibraryError(f"cannot create the maps folder {path}: {err.strerror or err}") from err
    return path


@dataclass
class MapEntry:
    """One IndoorGML source in the folder and the maps generated from it."""

    name: str
    source: Path
    size: int
    generated: list[GeneratedMap] = field(default_factory=list)
    sha256: str = ""

    @property
    def status(self) -> str:
        """``not converted`` / ``converted`` / ``stale`` (source changed since) / ``broken``."""
        if not self.generated:
            return "not converted"
        if any(g.broken for g in self.generated):
            return "broken"
        if any(g.stale for g in self.generated):
            return "stale"
        return "converted"


class MapsFolder:
    """List, import, download, convert and delete maps in one folder.

    Args:
        root: the folder; defaults to :func:`default_maps_dir`. It is created when first written to.
        allow_local: downloads may reach loopback and LAN addresses (labs); None reads the environment
            (``pmk dashboard --allow-local`` sets it for the kernel).
    """

    def __init__(self, root: str | os.PathLike[str] | None = None, *, allow_local: bool | None = None) -> None:
        self.root = Path(root).expanduser() if root is not None else default_maps_dir()
        self.allow_local = os.environ.get(ALLOW_LOCAL_ENV) == "1" if allow_local is None else bool(allow_local)
        self._sha_cache: dict[Path, tuple[int, int, str]] = {}
        self._storey_cache = StoreyCache()

    def __repr__(self) -> str:
        return f"MapsFolder({str(self.root)!r})"

    # ----------------------------------------------------------------- listing
    def _sources(self) -> dict[str, Path]:
        if not self.root.is_dir():
            return {}
        found: dict[str, Path] = {}
        for path in sorted(self.root.iterdir(), key=lambda p: (p.suffix.lower() != ".gml", p.name)):
            if path.name.startswith(".") or path.suffix.lower() not in SOURCE_SUFFIXES or not path.is_file():
                continue
            found.setdefault(path.stem, path)  # NAME.gml wins over NAME.xml
        return found

    def _sha256(self, path: Path) -> str:
        st = path.stat()
        cached = self._sha_cache.get(path)
        if cached and cached[:2] == (st.st_size, st.st_mtime_ns):
            return cached[2]
        digest = hashlib.sha256()
        with open(path, "rb") as fh:
            while chunk := fh.read(1 << 20):
                digest.update(chunk)
        self._sha_cache[path] = (st.st_size, st.st_mtime_ns, digest.hexdigest())
        return digest.hexdigest()

    def list(self) -> list[MapEntry]:
        """Every IndoorGML file (``*.gml``, ``*.xml``) sorted by name, with its generated maps."""
        sources = self._sources()
        generated = scan_generated(self.root, sources)
        entries = []
        for name in sorted(sources, key=lambda n: (n.casefold(), n)):
            path = sources[name]
            try:
                size, sha = path.stat().st_size, self._sha256(path)
            except OSError:
                continue  # vanished while listing
            maps = generated.get(name, [])
            for gm in maps:
                gm.stale = bool(gm.source_sha256) and gm.source_sha256 != sha
            entries.append(MapEntry(name=name, source=path, size=size, generated=maps, sha256=sha))
        return entries

    def orphans(self) -> builtins.list[GeneratedMap]:
        """Map YAMLs in the folder that belong to no IndoorGML source (e.g. copied in by hand)."""
        return scan_generated(self.root, self._sources()).get("", [])

    def exists(self, name: str) -> bool:
        return _lookup_name(name) in self._sources()

    def entry(self, name: str) -> MapEntry:
        """The entry called ``name``; LibraryError listing the known names if there is none."""
        key = _lookup_name(name)
        for e in self.list():
            if e.name == key:
                return e
        known = ", ".join(e.name for e in self.list()) or "none"
        raise LibraryError(f"no map named {key!r} in {self.root} (maps: {known})")

    def storeys(self, name: str) -> builtins.list[StoreyInfo]:
        """Storeys of map ``name`` (cells, doors, extent), known before it is converted.

        Read from the source once and cached while its mtime and size are unchanged.

        Raises:
            LibraryError: unknown map, or a source that cannot be read as IndoorGML.
        """
        entry = self.entry(name)
        return self._storey_cache.get(entry.source, entry.name)

    def cached_storeys(self, map_: str | MapEntry) -> builtins.list[StoreyInfo] | None:
        """The storeys of a map (name or entry) if already read for its file as it is now; never reads it."""
        source = map_.source if isinstance(map_, MapEntry) else self._sources().get(_lookup_name(map_))
        return None if source is None else self._storey_cache.cached(source)

    @property
    def storey_reads(self) -> int:
        """How many source files :meth:`storeys` has parsed (cache misses)."""
        return self._storey_cache.reads

    def require_root(self) -> None:
        """Raise :class:`MapsFolderMissing` when the folder is not there (reading it would find nothing)."""
        if not self.root.is_dir():
            raise MapsFolderMissing(str(self.root))

    # ----------------------------------------------------------------- adding sources
    def _ensure_root(self) -> None:
        try:
            self.root.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise LibraryError(f"cannot create the maps folder {self.root}: {err.strerror or err}") from err
        if not self.root.is_dir():
            raise LibraryError(f"the maps folder {self.root} is not a directory")

    def _refuse_existing(self, name: str, overwrite: bool) -> None:
        if not overwrite and self.exists(name):
            raise AlreadyExists(f"map {name!r} already exists; pass overwrite=True to replace it", name=name)

    def _add_source(
        self,
        name: str,
        overwrite: bool,
        suffix: str,
        write: Callable[[IO[bytes]], None],
        source: str,
        *,
        what: str,
        failure: str,
    ) -> MapEntry:
        """Add map ``name``: ``write`` fills a scratch file that is checked to be IndoorGML, then its
        checked bytes replace NAME.gml atomically, so a failure leaves an existing map untouched.
        ``failure`` prefixes OS errors; ``source`` ("file" or "url") picks the advice for a non-XML file."""
        try:
            with tempfile.NamedTemporaryFile(prefix=f".{name}.", suffix=suffix, dir=self.root) as scratch:
                write(scratch)
                scratch.flush()
                check_indoorgml(Path(scratch.name), what=what, source=source)  # installed = checked
                self._refuse_existing(name, overwrite)  # another writer may have taken the name meanwhile
                scratch.seek(0)
                return self._install(scratch, name)
        except OSError as err:
            raise LibraryError(f"{failure}: {err.strerror or err}", name=name) from err

    def _install(self, checked: IO[bytes], name: str) -> MapEntry:
        """Write the checked file as NAME.gml (0644: the folder is shared like the original ALMA_MAPS);
        drops a NAME.xml it replaces."""
        target = self.root / f"{name}.gml"
        old = self._sources().get(name)
        atomic_write(target, lambda out: shutil.copyfileobj(checked, out, 1 << 20))
        if old is not None and old != target:
            old.unlink(missing_ok=True)
        return self.entry(name)

    def import_file(
        self, path: str | os.PathLike[str], name: str | None = None, *, overwrite: bool = False, label: str = ""
    ) -> MapEntry:
        """Copy an IndoorGML file into the folder as ``NAME.gml`` (name defaults to the file's stem).
        ``label`` names the file in messages (an upload's own name; ``path`` is then a temp copy).

        Raises:
            LibraryError: missing file, invalid name, name taken without ``overwrite``, not IndoorGML.
        """
        src = Path(path).expanduser()
        shown = label or str(src)
        if not src.is_file():
            why = "a folder, not a .gml file" if src.is_dir() else "no such file"
            raise LibraryError(f"cannot import {shown}: {why}")
        name = check_name(name if name is not None else src.stem)
        self._refuse_existing(name, overwrite)
        self._ensure_root()
        current = self._sources().get(name)
        if current is not None and current.exists() and current.samefile(src):
            raise LibraryError(f"{shown} is already map {name!r} in {self.root}")

        def copy(out: IO[bytes]) -> None:
            with open(src, "rb") as inp:
                shutil.copyfileobj(inp, out, 1 << 20)

        failure = f"cannot import {shown} into {self.root}"
        return self._add_source(name, overwrite, ".import", copy, "file", what=shown, failure=failure)

    def download(
        self,
        url: str,
        name: str,
        *,
        overwrite: bool = False,
        timeout: float = DEFAULT_TIMEOUT,
        max_bytes: int = DEFAULT_MAX_BYTES,
        deadline: float = DEFAULT_DEADLINE,
        progress: ProgressCallback | None = None,
    ) -> MapEntry:
        """Download an IndoorGML map from an http(s) URL into ``NAME.gml`` (thesis 3.2.1).

        The name is checked before any network access; the body goes to a temp file that is checked
        to be IndoorGML and then renamed into place, so a failure leaves no file behind and an
        existing map untouched. Only public addresses are reached unless the folder ``allow_local``.

        Raises:
            LibraryError: invalid name or URL, name taken without ``overwrite``, DNS / connection /
                HTTP / timeout / size failures, a body that is not XML or not IndoorGML.
        """
        name = check_name(name)
        self._refuse_existing(name, overwrite)
        check_url(url)
        self._ensure_root()

        def save(out: IO[bytes]) -> None:
            fetch(
                url,
                out,
                timeout=timeout,
                deadline=deadline,
                max_bytes=max_bytes,
                progress=progress,
                allow_local=self.allow_local,
            )

        failure = f"cannot save the download as {name!r} in {self.root}"
        return self._add_source(name, overwrite, ".part", save, "url", what=f"the file at {url}", failure=failure)

    # ----------------------------------------------------------------- convert / delete
    def convert(
        self,
        name: str,
        resolution: float,
        *,
        storeys: builtins.list[str] | None = None,
        wall_thickness: float = DEFAULT_WALL_THICKNESS,
        unit: str = "auto",
        image_format: str = "pgm",
        progress: ProgressCallback | None = None,
        max_wall_gap: float = DEFAULT_MAX_WALL_GAP,
        door_width: float = DEFAULT_DOOR_WIDTH,
        chair_width: float = DEFAULT_CHAIR_WIDTH,
        not_windows: Sequence[str] = (),
        layers: Sequence[str] = (),
    ) -> builtins.list[GeneratedMap]:
        """Generate map_server files for every (or the given) storey of map ``name`` (thesis 3.2.2):
        :meth:`convert_with` the :class:`~pmk_nb.library.convert.ConvertOptions` these keywords make.

        Args:
            resolution: metres per cell (e.g. 0.05).
            storeys: storey names to convert; default all.
            max_wall_gap: openings reach this far across walls left out as gaps; gaps are wall up to max(this, 1 m).
            progress: :class:`~pmk_nb.progress.Progress` reports (read, rasterise, write, done).
            not_windows: cells (names or ids) the window/sill rule must leave navigable; layers: layers to draw.

        Raises:
            LibraryError: unknown map, bad arguments, or any reader / rasteriser / writer error
                (chained as ``__cause__``, e.g. a :class:`~pmk_nb.errors.GridTooLarge`, with its message).
        """
        options = ConvertOptions(
            resolution=resolution,
            unit=unit,
            storeys=storeys,
            wall_thickness=wall_thickness,
            max_wall_gap=max_wall_gap,
            layers=tuple(layers),
            image_format=image_format,
            door_width=door_width,
            chair_width=chair_width,
            not_windows=tuple(not_windows),
        )
        return self.convert_with(name, options, progress=progress)

    def convert_with(
        self, name: str, options: ConvertOptions, *, progress: ProgressCallback | None = None
    ) -> builtins.list[GeneratedMap]:
        """Convert map ``name`` with ``options`` passed whole: runs :func:`pmk_nb.library.convert.convert_plan`
        (all storeys or none are written), then removes the files of storeys that no longer exist.

        Raises:
            LibraryError: as :meth:`convert`.
        """
        entry = self.entry(name)
        resolution = options.resolution
        self._ensure_root()
        st = entry.source.stat()
        old = scan_generated(self.root, self._sources()).get(entry.name, [])
        try:
            result = convert_plan(
                entry.source,
                self.root,
                entry.name,
                None,
                options,
                extra_meta={"map": entry.name, "source": entry.source.name},
                progress=progress,
            )
        except (IndoorGMLError, OccupancyError, MapFormatError) as err:
            raise LibraryError(f"cannot convert map {entry.name!r}: {err}", name=entry.name) from err
        except MemoryError as err:
            raise LibraryError(
                f"cannot convert map {entry.name!r}: out of memory at {resolution} m per cell.",
                name=entry.name,
                hint="Use a coarser resolution (a larger number).",
            ) from err
        default = options.unit == "auto" and not options.layers and options.crs == "auto"
        if default:  # what storeys() reads too (the plan as read by default)
            self._storey_cache.put(entry.source, (st.st_mtime_ns, st.st_size), result.building)
        new_names = {p.name for m in result.maps for p in (m.files.yaml, m.files.image, m.files.preview, m.rooms) if p}
        self._remove_superseded(old, new_names, set(result.stems.values()))
        wanted = {m.files.yaml.stem for m in result.maps}
        return [g for g in self.entry(entry.name).generated if g.yaml.stem in wanted]

    def _remove_superseded(
        self, old: builtins.list[GeneratedMap], new_names: set[str], current_stems: set[str]
    ) -> None:
        """Delete old files the new set does not reuse: other image formats, storeys now gone.

        A storey that still exists but was not converted this time keeps its files, and so does a
        map matched only by its file name (it may have been put there by hand).
        """
        for gm in old:
            if gm.yaml.name not in new_names and (gm.yaml.stem in current_stems or not gm.tagged):
                continue
            for path in (gm.yaml, gm.image, gm.preview, sidecar_path(gm.yaml)):
                # only our own folder: a hand-written YAML may point at an image elsewhere
                if path is not None and path.parent == self.root and path.name not in new_names:
                    with contextlib.suppress(FileNotFoundError):
                        path.unlink()

    def delete(self, name: str) -> None:
        """Remove the source of map ``name`` and every map generated from it.

        Maps matched only by a ``NAME_*`` file name (not written by :meth:`convert`) are kept.
        """
        entry = self.entry(name)
        for gm in entry.generated:
            if not (gm.tagged or gm.yaml.stem == entry.name):
                continue
            for path in (gm.yaml, gm.image, gm.preview, sidecar_path(gm.yaml)):
                if path is not None and path.parent == self.root:
                    with contextlib.suppress(FileNotFoundError):
                        path.unlink()
        self._storey_cache.forget(entry.source)
        try:
            entry.source.unlink()
        except FileNotFoundError:
            pass
        except OSError as err:
            raise LibraryError(f"cannot delete {entry.source}: {err.strerror or err}") from err


def _lookup_name(name: str) -> str:
    """Name of an existing map: lenient (files dropped in by hand may have any name) but never a path."""
    if not isinstance(name, str) or not name or "/" in name or "\\" in name or name.startswith("."):
        raise LibraryError(f"invalid map name {name!r}")
    return name[:-4] if name.lower().endswith(SOURCE_SUFFIXES) else name
