"""What a tablet remembers about catalogues: the URLs it browses (settings) and what it installed from where.

``CatalogueSources`` is a small JSON file in the settings folder (0600, written atomically).
``InstallRecord`` is ``.catalogue-installs.json`` in the maps folder, beside the files it describes
(hidden: the folder's listing never shows it): per map, the catalogue it came from and the SHA-256
of each file installed, which is how the Catalogue tab tells "new" from "changed since installed".
"""

from __future__ import annotations

import contextlib
import datetime as dt
import json
from pathlib import Path
from typing import Any

from pmk_nb.catalogue.remote import Building
from pmk_nb.errors import SettingsError
from pmk_nb.fileio import atomic_write
from pmk_nb.library import check_url

SOURCES_FILE = "catalogues.json"
RECORD_FILE = ".catalogue-installs.json"
MAX_SOURCES = 50
NEW, CHANGED, INSTALLED = "new", "changed", "installed"


def read_json_object(path: Path) -> dict[str, Any]:
    """A JSON object from ``path``; {} when it is missing, unreadable or not an object (a fresh start)."""
    with contextlib.suppress(OSError, ValueError):
        data = json.loads(path.read_text(encoding="utf-8"))
        if isinstance(data, dict):
            return data
    return {}


class CatalogueSources:
    """The catalogue URLs kept in the settings folder, in the order they were added."""

    def __init__(self, config_dir: Path) -> None:
        self.path = Path(config_dir) / SOURCES_FILE

    def urls(self) -> list[str]:
        raw = read_json_object(self.path).get("catalogues")
        return [u for u in raw if isinstance(u, str)] if isinstance(raw, list) else []

    def add(self, url: str) -> list[str]:
        """Add an http(s) URL (checked; LibraryError when malformed); returns the list."""
        if not isinstance(url, str):
            raise SettingsError("a catalogue URL must be text")
        url = url.strip()
        check_url(url)
        urls = self.urls()
        if url not in urls:
            if len(urls) >= MAX_SOURCES:
                raise SettingsError(f"at most {MAX_SOURCES} catalogues; remove one first")
            urls.append(url)
            self._save(urls)
        return urls

    def remove(self, url: str) -> list[str]:
        urls = [u for u in self.urls() if u != url]
        self._save(urls)
        return urls

    def _save(self, urls: list[str]) -> None:
        atomic_write(self.path, json.dumps({"catalogues": urls}, indent=2) + "\n", mode=0o600, mkdir=True)


class InstallRecord:
    """Which catalogue each map came from, and the SHA-256 of each of its files then."""

    def __init__(self, maps_root: Path) -> None:
        self.path = Path(maps_root) / RECORD_FILE

    def get(self, name: str) -> dict[str, Any] | None:
        entry = (read_json_object(self.path).get("installs") or {}).get(name)
        return entry if isinstance(entry, dict) else None

    def put(self, name: str, catalogue_url: str, files: dict[str, str], *, all_storeys: bool) -> None:
        data = read_json_object(self.path)
        found = data.get("installs")
        installs: dict[str, Any] = found if isinstance(found, dict) else {}
        stamp = dt.datetime.now(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
        installs[name] = {
            "catalogue": catalogue_url,
            "installed": stamp,
            "files": files,
            "all_storeys": all_storeys,
        }
        atomic_write(self.path, json.dumps({"installs": installs}, indent=2, sort_keys=True) + "\n")

    def status(self, building: Building, catalogue_url: str, *, present: bool) -> str:
        """``new`` (never installed from this catalogue, or deleted since), ``changed`` (a file
        installed then differs now, or a storey was added), ``installed`` (as in the catalogue)."""
        rec = self.get(building.id)
        if not present or rec is None or rec.get("catalogue") != catalogue_url:
            return NEW
        files = rec.get("files") or {}
        now = {a.file_name: a.sha256 for s in building.storeys for k, a in s.assets.items() if k != "thumbnail"}
        if building.source is not None:
            now[building.source.file_name] = building.source.sha256
        if any(now.get(n) != sha for n, sha in files.items()):
            return CHANGED
        maps_now = {n for n in now if n.endswith((".yaml", ".yml"))}
        return CHANGED if rec.get("all_storeys") and maps_now - set(files) else INSTALLED
