"""Files offered for download from the page: a recording, the current map (YAML + image as a zip).

A Voilà page has no file server for the tablet's folders, so a download is an ``<a download>`` link
whose address holds the file itself (a ``data:`` URL): it works the same in Voilà and JupyterLab,
and nothing outside the page can fetch it. Files above :data:`PAGE_LIMIT` are not put in the page
(the widget state would carry them); the link's place then says where the file is.
"""

from __future__ import annotations

import base64
import io
import zipfile
from pathlib import Path

from pmk_nb.rosmap import read_map_yaml
from pmk_nb.ui.common.widgets import escape

PAGE_LIMIT = 25 * 1024 * 1024  # bytes a download link may carry inside the page


def size_text(size: int) -> str:
    return f"{size / 1e6:.1f} MB" if size >= 100_000 else f"{max(1, round(size / 1e3))} kB"


def link_html(data: bytes, file_name: str, label: str, css_class: str, media_type: str) -> str:
    """An ``<a download>`` link carrying ``data``; a note instead when it is too big for the page."""
    if len(data) > PAGE_LIMIT:
        too_big = f"{size_text(len(data))}, too big to download from the page"
        return f'<span class="{css_class}">{escape(label)}: {too_big}.</span>'
    href = f"data:{media_type};base64,{base64.b64encode(data).decode('ascii')}"
    return (
        f'<a class="{css_class}" download="{escape(file_name)}" href="{href}">'
        f"{escape(label)} ({size_text(len(data))})</a>"
    )


def file_link_html(path: Path, label: str, css_class: str, media_type: str = "application/octet-stream") -> str:
    """A download link for the file ``path`` (read now), or where it is when it is too big."""
    size = path.stat().st_size
    if size > PAGE_LIMIT:
        return f'<span class="{css_class}">{escape(label)}: {size_text(size)} in {escape(path)}</span>'
    return link_html(path.read_bytes(), path.name, label, css_class, media_type)


def map_zip(yaml_path: Path) -> tuple[str, bytes]:
    """(zip file name, zip bytes) of a map: its YAML and the image it names, read through the one YAML reader.

    Raises:
        MapLoadError: the YAML cannot be read; OSError: the image cannot be read.
    """
    meta = read_map_yaml(yaml_path)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.write(meta.path, meta.path.name)
        inside = Path(meta.image_text)
        plain = not inside.is_absolute() and ".." not in inside.parts  # else a zip entry could leave its folder
        zf.write(meta.image, meta.image_text if plain else meta.image.name)
    return f"{meta.path.stem}.zip", buf.getvalue()
