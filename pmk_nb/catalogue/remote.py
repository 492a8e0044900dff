"""Read a published map catalogue over http(s): buildings, storeys, and every asset's URL, size and SHA-256.

Everything goes through the library's one downloader (:func:`pmk_nb.library.download.fetch`: size
cap, deadline, public addresses only unless allowed, each redirect checked). A catalogue is trusted
only with its own folder: every link and asset must resolve inside the folder of ``catalog.json``,
over the same scheme; an absolute path, a ``..`` that climbs out, another host (unless allowed) or a
redirect elsewhere is refused with a typed error before anything is installed.
"""

from __future__ import annotations

import io
import json
import posixpath
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import IO, Any
from urllib.parse import unquote, urljoin, urlsplit

from pmk_nb.catalogue.hashes import sha256_of_multihash
from pmk_nb.errors import (
    AssetOutsideCatalogue,
    CatalogueError,
    DownloadError,
    DownloadTooLarge,
    LibraryError,
    RedirectRefused,
)
from pmk_nb.library import check_url, fetch
from pmk_nb.progress import ProgressCallback

MAX_DOC_BYTES = 4 * 1024 * 1024  # one STAC JSON document
MAX_DOCS = 2000  # documents read for one catalogue (a bound on a hostile or looping one)


@dataclass(frozen=True)
class Asset:
    """One file of the catalogue: where it is, its size and hex SHA-256 as declared."""

    key: str
    url: str
    size: int
    sha256: str
    media_type: str = ""

    @property
    def file_name(self) -> str:
        return unquote(urlsplit(self.url).path.rsplit("/", 1)[-1])


@dataclass(frozen=True)
class Storey:
    """An Item: one storey's map."""

    id: str
    title: str
    storey: str | None
    resolution: float
    width: int
    height: int
    updated: str
    assets: dict[str, Asset]
    geometry: dict[str, Any] | None = None

    @property
    def size(self) -> int:
        """Bytes installed for this storey (thumbnail and shared source excluded)."""
        return sum(a.size for k, a in self.assets.items() if k not in ("thumbnail", "indoorgml"))


@dataclass(frozen=True)
class Building:
    """A Collection: one building, its IndoorGML source and its storeys."""

    id: str
    title: str
    description: str
    source: Asset | None
    storeys: list[Storey] = field(default_factory=list)

    @property
    def updated(self) -> str:
        return max((s.updated for s in self.storeys), default="")

    @property
    def size(self) -> int:
        return (self.source.size if self.source else 0) + sum(s.size for s in self.storeys)


@dataclass(frozen=True)
class RefusedBuilding:
    """A building of the catalogue that could not be read or checked; the others are still listed (issue 40).

    ``error`` is the typed refusal (AssetOutsideCatalogue, RedirectRefused, CatalogueError, DownloadError);
    ``id`` is the folder its collection sits in, the building's id in a catalogue ``pmk maps publish`` wrote.
    """

    url: str
    error: LibraryError

    @property
    def id(self) -> str:
        return unquote(posixpath.basename(posixpath.dirname(urlsplit(self.url).path)))


@dataclass(frozen=True)
class Catalogue:
    url: str
    title: str
    buildings: list[Building]
    refused: list[RefusedBuilding] = field(default_factory=list)

    def building(self, name: str) -> Building:
        """The building ``name``; a refused one raises its own refusal (nothing of it can be installed)."""
        for b in self.buildings:
            if b.id == name:
                return b
        for r in self.refused:
            if r.id == name:
                raise r.error
        known = ", ".join(b.id for b in self.buildings) or "none"
        raise CatalogueError(f"{self.url}: no building {name!r} (buildings: {known})", url=self.url, name=name)


class Reader:
    """Fetches and checks documents of one catalogue (its folder, scheme and allowed hosts)."""

    def __init__(
        self, url: str, *, allow_local: bool = False, allow_hosts: Iterable[str] = (), timeout: float = 30.0
    ) -> None:
        url = url.strip()
        check_url(url)
        self.url = url if url.endswith(".json") else url.rstrip("/") + "/catalog.json"
        self.root = self.url.rsplit("/", 1)[0] + "/"
        parts = urlsplit(self.root)
        self.scheme, self.host = parts.scheme.lower(), (parts.hostname or "").lower()
        self.allow_hosts = {h.strip().lower() for h in allow_hosts if h.strip()}
        self.allow_local = allow_local
        self.timeout = timeout
        self.docs = 0

    def resolve(self, base: str, href: object) -> str:
        """The absolute URL of ``href`` read in the document at ``base``; refused unless inside the folder."""
        if not isinstance(href, str) or not href or "\\" in href or href.startswith("/"):
            raise AssetOutsideCatalogue(url=base, href=str(href), root=self.root)
        target = urljoin(base, href)
        if not self.inside(target):
            raise AssetOutsideCatalogue(url=base, href=href, root=self.root)
        return target

    def inside(self, target: str) -> bool:
        """Same scheme and either an allowed host, or this host and a path under the folder ('..' and
        its percent-encoded spellings resolved first)."""
        parts = urlsplit(target)
        if parts.scheme.lower() != self.scheme:
            return False
        netloc = parts.netloc.lower()
        if netloc != urlsplit(self.root).netloc.lower():  # another host: only one allowed (name or name:port)
            return bool({(parts.hostname or "").lower(), netloc} & self.allow_hosts) and "@" not in netloc
        raw = unquote(parts.path)
        if "\\" in raw or "\x00" in raw or any(seg in ("..", ".") for seg in raw.split("/")[1:-1]):
            return False
        root_path = unquote(urlsplit(self.root).path)
        return posixpath.normpath(raw).startswith(root_path.rstrip("/") + "/")

    def check_redirect(self, url: str, target: str) -> None:
        """A redirect may not change the scheme (https -> http) nor leave the catalogue's folder."""
        if urlsplit(target).scheme.lower() != urlsplit(url).scheme.lower() or not self.inside(urljoin(url, target)):
            raise RedirectRefused(url=url, target=target)

    def fetch_to(self, url: str, out: IO[bytes], *, max_bytes: int, progress: ProgressCallback | None = None) -> int:
        return fetch(
            url,
            out,
            timeout=self.timeout,
            max_bytes=max_bytes,
            progress=progress,
            allow_local=self.allow_local,
            redirect_check=self.check_redirect,
        )

    def document(self, url: str) -> dict[str, Any]:
        """One JSON document (at most 4 MiB; at most 2000 per catalogue)."""
        self.docs += 1
        if self.docs > MAX_DOCS:
            raise CatalogueError(f"{self.url}: more than {MAX_DOCS} documents; refused", url=self.url)
        buf = io.BytesIO()
        try:
            self.fetch_to(url, buf, max_bytes=MAX_DOC_BYTES)
        except DownloadTooLarge as err:
            raise CatalogueError(f"{url}: a STAC document over {MAX_DOC_BYTES} bytes; refused", url=url) from err
        try:
            doc = json.loads(buf.getvalue().decode("utf-8"))
        except (UnicodeDecodeError, ValueError) as err:
            raise CatalogueError(f"{url} is not a STAC JSON document: {err}", url=url) from err
        if not isinstance(doc, dict):
            raise CatalogueError(f"{url} is not a STAC JSON document (not an object)", url=url)
        return doc

    def links(self, doc: dict[str, Any], base: str, rel: str) -> list[str]:
        found = [lk for lk in doc.get("links") or [] if isinstance(lk, dict) and lk.get("rel") == rel]
        return [self.resolve(base, lk.get("href")) for lk in found]

    def asset(self, key: str, raw: object, base: str) -> Asset:
        if not isinstance(raw, dict):
            raise CatalogueError(f"{base}: asset {key!r} is not an object", url=base)
        url = self.resolve(base, raw.get("href"))
        size, sha = raw.get("file:size"), sha256_of_multihash(raw.get("file:checksum"))
        if not isinstance(size, int) or isinstance(size, bool) or size < 0 or sha is None:
            raise CatalogueError(
                f"{base}: asset {key!r} lacks a file:size or a sha2-256 file:checksum; it cannot be verified", url=base
            )
        return Asset(key=key, url=url, size=size, sha256=sha, media_type=str(raw.get("type") or ""))


def read_catalogue(
    url: str, *, allow_local: bool = False, allow_hosts: Iterable[str] = (), timeout: float = 30.0
) -> Catalogue:
    """The buildings and storeys of the catalogue at ``url`` (``.../catalog.json`` or its folder).

    A building whose documents fail (missing, malformed, a link out of the catalogue) is left out of
    ``buildings`` and kept in ``refused`` with its error; the rest are listed.

    Raises:
        CatalogueError: the catalogue's own document is missing, malformed or unverifiable; AssetOutsideCatalogue,
            RedirectRefused: a link of it leaves the catalogue; DownloadError: the network said no.
    """
    reader = Reader(url, allow_local=allow_local, allow_hosts=allow_hosts, timeout=timeout)
    root = reader.document(reader.url)
    if root.get("type") not in ("Catalog", "Collection"):
        raise CatalogueError(f"{reader.url} is not a STAC catalogue (type {root.get('type')!r})", url=reader.url)
    buildings: list[Building] = []
    refused: list[RefusedBuilding] = []
    for child in reader.links(root, reader.url, "child"):
        try:
            buildings.append(_building(reader, child))
        except (CatalogueError, DownloadError) as err:  # one bad building never hides the clean ones
            refused.append(RefusedBuilding(child, err))
    title = str(root.get("title") or root.get("id") or "")
    return Catalogue(url=reader.url, title=title, buildings=buildings, refused=refused)


def _building(reader: Reader, url: str) -> Building:
    doc = reader.document(url)
    bid = str(doc.get("id") or "")
    assets = doc.get("assets") or {}
    source = reader.asset("indoorgml", assets["indoorgml"], url) if "indoorgml" in assets else None
    storeys = [_storey(reader, u) for u in reader.links(doc, url, "item")]
    return Building(
        id=bid,
        title=str(doc.get("title") or bid),
        description=str(doc.get("description") or ""),
        source=source,
        storeys=sorted(storeys, key=lambda s: (s.storey or "", s.id)),
    )


def _storey(reader: Reader, url: str) -> Storey:
    doc = reader.document(url)
    props = doc.get("properties") or {}
    raw_assets = doc.get("assets") or {}
    assets = {str(k): reader.asset(str(k), v, url) for k, v in raw_assets.items()}
    storey = props.get("pmk:storey")
    return Storey(
        id=str(doc.get("id") or ""),
        title=str(props.get("title") or doc.get("id") or ""),
        storey=None if storey is None else str(storey),
        resolution=_num(props.get("pmk:resolution"), float),
        width=int(_num(props.get("pmk:width"), int)),
        height=int(_num(props.get("pmk:height"), int)),
        updated=str(props.get("updated") or props.get("datetime") or ""),
        assets=assets,
        geometry=doc.get("geometry") if isinstance(doc.get("geometry"), dict) else None,
    )


def _num(value: object, kind: type) -> float:
    return float(value) if isinstance(value, int | float) and not isinstance(value, bool) else 0.0
