"""What a map server may open: files inside its maps folder, images it can afford to decode.

Issue 30: the chair's map server confined the YAML a request names but not the image that YAML
names (``image: /home/pmk/.ssh/id_rsa`` or a symlink out of the folder was opened), and a 165 KB PNG
declaring 12000 x 12000 pixels took 1.9 GB to decode. Both checks run before the image is opened
for decoding: the real path (symlinks followed) against the folder, the header's size against a cap.
"""

from __future__ import annotations

import os
from pathlib import Path

from pmk_nb.errors import MapImageTooLarge, MapOutsideFolder
from pmk_nb.rosmap.image import header_size

#: Pixels a map reader decodes by default: decoding costs ~13 bytes a pixel (the RGBA view, the
#: loader's view, the cells), so 100 M pixels is ~1.3 GB at peak, what a chair's computer can spare
#: (a 2.5 x 2.5 km floor at 0.25 m, or 500 x 500 m at 0.05 m). A site with larger maps and the memory
#: for them raises it with ``PMK_MAP_MAX_PIXELS`` (or ``read_map(max_pixels=...)``).
MAX_MAP_PIXELS = 100_000_000
PIXELS_ENV = "PMK_MAP_MAX_PIXELS"


def pixel_cap() -> int:
    """The cap in force: ``PMK_MAP_MAX_PIXELS`` when it is a positive integer, else MAX_MAP_PIXELS."""
    raw = os.environ.get(PIXELS_ENV, "").strip().replace("_", "")
    return int(raw) if raw.isdigit() and int(raw) > 0 else MAX_MAP_PIXELS


def confine(path: Path, folder: Path, *, what: str, yaml: Path | None = None) -> None:
    """Raise MapOutsideFolder unless ``path``'s real path (every symlink followed) lies in ``folder``."""
    root = Path(os.path.realpath(folder))
    real = Path(os.path.realpath(path))
    if real == root or not real.is_relative_to(root):
        named = f"{yaml}: the image {path}" if yaml is not None else f"{path}"
        raise MapOutsideFolder(
            f"{named} lies outside the maps folder {root} (it resolves to {real}); refused",
            path=str(path),
            folder=str(root),
            what=what,
        )


def image_size(path: Path) -> tuple[int, int] | None:
    """(width, height) from the header: PGM/PNG/BMP parsed here, other formats by Pillow's lazy open
    (reads the header only); None when Pillow itself refuses the size as a decompression bomb."""
    size = header_size(path)
    if size is not None:
        return size
    from PIL import Image

    try:
        with Image.open(path) as im:  # no load(): only the header is read
            return im.size
    except Image.DecompressionBombError:
        return None


def check_pixels(path: Path, limit: int = MAX_MAP_PIXELS) -> None:
    """Raise MapImageTooLarge when the image at ``path`` declares more than ``limit`` pixels.

    OSError (missing file) and Pillow's errors for a file that is no image propagate: the caller
    reports them as it reports a decoding failure.
    """
    size = image_size(path)
    if size is not None and size[0] * size[1] <= limit:
        return
    shown = f"{size[0]}x{size[1]} pixels" if size is not None else "too many pixels for the image decoder"
    raise MapImageTooLarge(
        f"{path}: {shown}, more than the {limit:,} a map server decodes (checked from the header, not decoded)",
        path=str(path),
        width=size[0] if size else None,
        height=size[1] if size else None,
        limit=limit,
    )
