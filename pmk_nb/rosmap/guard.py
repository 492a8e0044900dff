"""What a map server may open: files inside its maps folder, images it can afford to decode.

Issue 30: the chair's map server confined the YAML a request names but not the image that YAML
names (``image: /home/pmk/.ssh/id_rsa`` or a symlink out of the folder was opened), and a 165 KB PNG
declaring 12000 x 12000 pixels took 1.9 GB to decode. Issue 38: a PGM whose header comment ended in
CR read as 1x1 here while Pillow decoded 4000x4000, and a 16-bit or colour image costs far more a
pixel than an 8-bit gray one. So the cap is checked on the size and mode Pillow itself will decode
(opened, before ``load()``), priced by what decoding that mode costs, and a header that the decoder
reads otherwise than its grammar says is refused (:mod:`pmk_nb.rosmap.header`).
"""

from __future__ import annotations

import os
from pathlib import Path

from pmk_nb.errors import MalformedImageHeader, MapImageTooLarge, MapOutsideFolder

#: Pixels a map reader decodes by default, counted as 8-bit gray pixels (the maps map_saver writes):
#: ~1.6 GB at peak, what a chair's computer can spare (a 2.5 x 2.5 km floor at 0.25 m, or 500 x 500 m
#: at 0.05 m). Other kinds of image get the same memory: fewer pixels (:func:`pixels_allowed`). A
#: site with larger maps and the memory for them raises it with ``PMK_MAP_MAX_PIXELS`` (or
#: ``read_map(max_pixels=...)``).
MAX_MAP_PIXELS = 100_000_000
PIXELS_ENV = "PMK_MAP_MAX_PIXELS"

#: Peak bytes a pixel to read a map, by Pillow mode: the worst of the three readers and three map
#: modes, measured as peak RSS (tests/rosmap/test_image_header.py keeps them true) and rounded up.
#: 8-bit gray is looked up (~15); 16/32-bit gray is shifted to 8 bits first (I;16 ~30, I ~36);
#: anything with colour, alpha (or a gray with a transparent value), a palette or 1-bit pixels takes
#: the readers' float maths on four channels (~88).
GRAY8_BYTES = 16
DECODE_BYTES_PER_PIXEL = {"L": GRAY8_BYTES, "I;16": 34, "I;16L": 34, "I;16B": 34, "I;16N": 34, "I": 38, "F": 38}
OTHER_BYTES = 90


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


def decode_bytes(mode: str, transparency: bool = False) -> int:
    """Peak bytes a pixel to read an image of Pillow ``mode`` (with a transparent value or not)."""
    if transparency:
        return OTHER_BYTES
    return DECODE_BYTES_PER_PIXEL.get(mode, OTHER_BYTES)


def pixels_allowed(limit: int, mode: str, transparency: bool = False) -> int:
    """Pixels of this kind the cap ``limit`` (counted in 8-bit gray pixels) allows: the same memory."""
    return limit * GRAY8_BYTES // decode_bytes(mode, transparency)


def check_decode(path: Path, size: tuple[int, int], mode: str, transparency: bool, limit: int) -> None:
    """Raise MapImageTooLarge when decoding ``size`` pixels of ``mode`` would take more memory than
    ``limit`` 8-bit gray pixels do. ``size`` and ``mode`` are the decoder's own (an opened image,
    before ``load()``), never a second reading of the header."""
    width, height = size
    allowed = pixels_allowed(limit, mode, transparency)
    if width * height <= allowed:
        return
    kind = "" if allowed == limit else f" of {mode}{' with transparency' if transparency else ''}"
    cost = "" if allowed == limit else f" ({decode_bytes(mode, transparency)} bytes a pixel to decode)"
    raise MapImageTooLarge(
        f"{path}: {width}x{height} pixels{kind}{cost}, more than the {allowed:,} a map server decodes"
        f" (checked before decoding; {PIXELS_ENV} is {limit:,} 8-bit gray pixels)",
        path=str(path),
        width=width,
        height=height,
        limit=allowed,
        mode=mode,
    )


def refused_by_decoder(path: Path, declared: tuple[int, int] | None, limit: int) -> MapImageTooLarge:
    """The error for an image the decoder will not even open (over Pillow's decompression-bomb limit)."""
    shown = f"{declared[0]}x{declared[1]} pixels" if declared else "too many pixels for the image decoder"
    return MapImageTooLarge(
        f"{path}: {shown}, more than the {limit:,} a map server decodes (the decoder refuses to open it)",
        path=str(path),
        width=declared[0] if declared else None,
        height=declared[1] if declared else None,
        limit=limit,
    )


def check_agrees(path: Path, declared: tuple[int, int] | None, decoded: tuple[int, int]) -> None:
    """Raise MalformedImageHeader when the header, read by its grammar, gives another size than the
    decoder's: listings show the header's size and the two must never tell different stories."""
    if declared is None or tuple(declared) == tuple(decoded):
        return
    reason = f"its header reads {declared[0]}x{declared[1]} but the decoder reads {decoded[0]}x{decoded[1]}"
    raise MalformedImageHeader(f"{path}: {reason}; refused", path=str(path), reason=reason)
