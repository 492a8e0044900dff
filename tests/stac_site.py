"""Real parts for the catalogue tests (issue 27): a static web server with ETag and Range support,
and the schema map that lets stac-validator (an independent STAC validator) work offline.

The web server is Python's ``http.server`` taught what static hosts do (nginx, object stores):
a strong ``ETag`` per file, ``If-None-Match`` -> 304, ``Range: bytes=a-b`` -> 206. Tests may add
redirects (path -> Location) to check that the installer refuses a redirect to another scheme.
"""

from __future__ import annotations

import email.utils
import hashlib
import http.server
import json
import os
import re
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import pystac.validation

_RANGE = re.compile(r"^bytes=(\d*)-(\d*)$")


@dataclass
class Site:
    url: str  # http://127.0.0.1:PORT/ (the folder served)
    root: Path
    redirects: dict[str, str] = field(default_factory=dict)
    requests: list[tuple[str, str, int]] = field(default_factory=list)  # (path, Range header, status)


class _Handler(http.server.SimpleHTTPRequestHandler):
    site: Site

    def log_message(self, *args: object) -> None:
        pass

    def _etag(self, path: str) -> str | None:
        try:
            st = os.stat(path)
        except OSError:
            return None
        return '"' + hashlib.sha256(f"{st.st_size}:{st.st_mtime_ns}".encode()).hexdigest()[:32] + '"'

    def do_GET(self) -> None:
        target = self.site.redirects.get(self.path)
        if target is not None:
            self.send_response(302)
            self.send_header("Location", target)
            self.send_header("Content-Length", "0")
            self.end_headers()
            self.site.requests.append((self.path, "", 302))
            return
        path = self.translate_path(self.path)
        etag = self._etag(path)
        if etag is None or os.path.isdir(path):
            self.send_error(404)
            self.site.requests.append((self.path, "", 404))
            return
        if self.headers.get("If-None-Match") == etag:
            self.send_response(304)
            self.send_header("ETag", etag)
            self.end_headers()
            self.site.requests.append((self.path, "", 304))
            return
        data = Path(path).read_bytes()
        status, body, extra = 200, data, {}
        match = _RANGE.match(self.headers.get("Range", "").strip())
        if match and (match.group(1) or match.group(2)):
            first = int(match.group(1)) if match.group(1) else max(0, len(data) - int(match.group(2)))
            last = int(match.group(2)) if match.group(1) and match.group(2) else len(data) - 1
            last = min(last, len(data) - 1)
            if first > last:
                self.send_error(416)
                return
            status, body = 206, data[first : last + 1]
            extra["Content-Range"] = f"bytes {first}-{last}/{len(data)}"
        self.send_response(status)
        self.send_header("Content-Type", self.guess_type(path))
        self.send_header("Content-Length", str(len(body)))
        self.send_header("ETag", etag)
        self.send_header("Accept-Ranges", "bytes")
        self.send_header("Last-Modified", email.utils.formatdate(os.stat(path).st_mtime, usegmt=True))
        for k, v in extra.items():
            self.send_header(k, v)
        self.end_headers()
        self.wfile.write(body)
        self.site.requests.append((self.path, self.headers.get("Range", ""), status))


@contextmanager
def serve_static(root: Path) -> Iterator[Site]:
    """Serve ``root`` on 127.0.0.1 (a free port) until the block ends."""
    site = Site(url="", root=root)
    handler = type("Handler", (_Handler,), {"site": site})
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), lambda *a: handler(*a, directory=str(root)))
    site.url = f"http://127.0.0.1:{server.server_address[1]}/"
    thread = threading.Thread(target=server.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True)
    thread.start()
    try:
        yield site
    finally:
        server.shutdown()
        server.server_close()
        thread.join(5)


# -- offline schemas for stac-validator --------------------------------------------------------------
#: The STAC file extension's fields as its README defines them (written here: the validator would
#: fetch the published schema from the web, which tests must not need).
FILE_EXTENSION_SCHEMA = {
    "$schema": "http://json-schema.org/draft-07/schema#",
    "$id": "https://stac-extensions.github.io/file/v2.1.0/schema.json",
    "type": "object",
    "required": ["stac_extensions"],
    "properties": {
        "stac_extensions": {
            "type": "array",
            "contains": {"const": "https://stac-extensions.github.io/file/v2.1.0/schema.json"},
        },
        "assets": {"type": "object", "additionalProperties": {"$ref": "#/definitions/asset"}},
    },
    "definitions": {
        "asset": {
            "type": "object",
            "required": ["file:size", "file:checksum"],
            "properties": {
                "file:size": {"type": "integer", "minimum": 0},
                "file:checksum": {"type": "string", "pattern": "^[a-f0-9]+$"},
            },
        }
    },
}


def schema_map(tmp: Path) -> dict[str, str]:
    """Schema URL -> local file: the STAC 1.1.0 core and GeoJSON schemas pystac ships, and the file extension's."""
    base = Path(pystac.validation.__file__).parent / "jsonschemas"
    spec = base / "stac-spec" / "v1.1.0"
    web = "https://schemas.stacspec.org/v1.1.0"
    out = {
        f"{web}/catalog-spec/json-schema/catalog.json": spec / "catalog.json",
        f"{web}/collection-spec/json-schema/collection.json": spec / "collection.json",
        "https://geojson.org/schema/Feature.json": base / "geojson" / "Feature.json",
        "https://geojson.org/schema/Geometry.json": base / "geojson" / "Geometry.json",
    }
    for name in ("item", "basics", "datetime", "instrument", "licensing", "provider", "common", "bands", "data-values"):
        out[f"{web}/item-spec/json-schema/{name}.json"] = spec / f"{name}.json"
    ext = tmp / "file-extension-schema.json"
    ext.write_text(json.dumps(FILE_EXTENSION_SCHEMA))
    out["https://stac-extensions.github.io/file/v2.1.0/schema.json"] = ext
    return {k: str(v) for k, v in out.items()}
