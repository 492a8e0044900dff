"""Pixel semantics of map_server images: decode like ROS 1 / Nav2, and encode our own maps.

Three loaders exist in the wild and they disagree on edge cases, so each is copied exactly:

* ``ros1``: ROS 1 ``map_server/src/image_loader.cpp`` (SDL_image surface bytes). The mean of the
  surface's bytes per pixel (alpha averaged in for trinary), ``occ = (255 - mean) / 255``,
  ``occ > occupied_thresh`` -> 100, ``occ < free_thresh`` -> 0; scale mode ``1 + 98 * ratio``
  truncated; raw mode stores the byte unchanged (128..255 become negative int8). SDL hands ROS 1
  palette *indices* for paletted and 1-bit images, and the "alpha" it tests in scale mode is the last
  byte of the pixel (blue for RGB PNG, red for 24-bit BMP): both quirks are reproduced.
* ``nav2_humble``: Nav2 ``map_io.cpp`` up to Humble (GraphicsMagick Q16, per pixel): mean of R, G, B
  quantums (+ alpha in trinary when the image has a matte), ``occupied_thresh < occ``,
  ``occ < free_thresh``, scale ``rint``; raw ``round(shade * 255)`` kept when in 0..100.
* ``nav2_jazzy``: the Eigen rewrite (Jazzy and later): 8-bit luma gray, float32 maths,
  ``occ >= occupied_thresh``, ``occ <= free_thresh``, any alpha < 255 -> unknown.

Our writer only ever emits gray 0 / 254 / 205 without alpha, the one encoding all three read alike.
"""

from __future__ import annotations

from pathlib import Path
from typing import BinaryIO, Literal

import numpy as np

from pmk_nb.grid import GRAY_LUT as _GRAY_LUT
from pmk_nb.grid import GRAY_UNKNOWN as GRAY_UNKNOWN  # the greys are the grid's
from pmk_nb.grid import OccupancyGrid
from pmk_nb.rosmap.guard import check_agrees, check_decode, refused_by_decoder
from pmk_nb.rosmap.header import gray_pgm_layout, header_size

#: The map server image readers copied here; ``read_map(..., reader=...)`` picks one.
ImageReader = Literal["ros1", "nav2_humble", "nav2_jazzy"]
READERS: tuple[ImageReader, ...] = ("ros1", "nav2_humble", "nav2_jazzy")
MODES = ("trinary", "scale", "raw")
GRAY_OCCUPIED = 0
GRAY_FREE = 254


class DecodedImage:
    """What each loader sees of one image file.

    Attributes:
        rgba: (H, W, 4) uint8, palette resolved, gray expanded (what GraphicsMagick reports); for an
            opaque 8-bit gray file (``rgba=None`` given) expanded from ``sdl`` only when a reader asks:
            four bytes a pixel cost a 100 M-cell map 400 MB that the gray lookup never reads.
        has_alpha: the file carries transparency (GraphicsMagick ``matte()``).
        sdl: (H, W, C) uint8, the SDL_image surface bytes ROS 1 averages (C = 1, 3 or 4).
        sdl_alpha_mask: the SDL surface has an alpha mask (changes ROS 1's averaging in scale mode).
    """

    def __init__(
        self,
        *,
        rgba: np.ndarray | None,
        has_alpha: bool,
        sdl: np.ndarray,
        sdl_alpha_mask: bool,
        spent_by_reading: bool = False,
    ) -> None:
        self._rgba = rgba
        self.gray_only = rgba is None  # an opaque 8-bit gray image: sdl holds every reader's view
        # the pixels are this image's own (read from the file for it): reading may turn them into the
        # grid in place, one copy of a 100 M-cell map instead of two; the image is spent after that
        self.spent_by_reading = spent_by_reading
        self.has_alpha = has_alpha
        self.sdl = sdl
        self.sdl_alpha_mask = sdl_alpha_mask

    @property
    def rgba(self) -> np.ndarray:
        if self._rgba is None:
            gray = self.sdl[..., 0]
            self._rgba = np.stack([gray, gray, gray, np.full_like(gray, 255)], axis=2)
        return self._rgba

    @property
    def size(self) -> tuple[int, int]:
        """(height, width) in pixels."""
        return int(self.sdl.shape[0]), int(self.sdl.shape[1])


def decode_image(path: Path, *, max_pixels: int | None = None) -> DecodedImage:
    """Decode a PGM/PNG/BMP (anything Pillow reads) into the views each loader uses.

    With ``max_pixels`` (8-bit gray pixels, :mod:`pmk_nb.rosmap.guard`), the image Pillow opened is
    priced by its own size and mode before ``load()`` decodes a pixel; a Netpbm/PNG/BMP header must
    give Pillow's size by its grammar.

    Raises:
        MapImageTooLarge: over the cap. MalformedImageHeader: a header that breaks its grammar.
        OSError / ValueError: the file is missing or not a readable image (callers wrap these).
    """
    raw = _raw_gray_pgm(path, max_pixels)
    if raw is not None:
        return raw
    from PIL import Image

    declared = header_size(path)
    try:
        opened = Image.open(path)  # reads the header only
    except Image.DecompressionBombError as err:
        if max_pixels is None:
            raise
        raise refused_by_decoder(path, declared, max_pixels) from err
    with opened as im:
        if max_pixels is not None:
            check_decode(path, im.size, im.mode, "transparency" in im.info, max_pixels)
        check_agrees(path, declared, im.size)
        im.load()
        fmt = (im.format or "").upper()
        mode = im.mode
        has_alpha = mode in ("RGBA", "LA", "PA") or "transparency" in im.info
        if mode == "L" and not has_alpha:  # the common map: one gray byte a pixel, nothing else to see
            return DecodedImage(
                rgba=None, has_alpha=False, sdl=np.asarray(im, dtype=np.uint8)[..., None], sdl_alpha_mask=False
            )
        rgba = np.asarray(im.convert("RGBA"), dtype=np.uint8)
        if mode == "P":
            sdl = np.asarray(im, dtype=np.uint8)[..., None]  # SDL: 8-bit surface of palette indices
            sdl_amask = False
        elif mode == "1":
            sdl = np.asarray(im, dtype=np.uint8)[..., None]  # png_set_packing: 0/1 indices
            sdl_amask = False
        elif mode in ("L", "I;16", "I;16B", "I", "F"):
            if mode == "L":
                sdl = np.asarray(im, dtype=np.uint8)[..., None]
            else:  # 16-bit gray: libpng strip_16 keeps the high byte
                sdl = (np.asarray(im).astype(np.int64) >> 8).clip(0, 255).astype(np.uint8)[..., None]
                rgba = np.repeat(sdl, 3, axis=2)
                rgba = np.concatenate([rgba, np.full_like(sdl, 255)], axis=2)
            sdl_amask = False
        elif mode in ("LA", "RGBA", "PA"):
            sdl = rgba.copy()  # SDL_image expands gray+alpha to RGBA
            sdl_amask = True
        else:
            rgb = rgba[..., :3]
            sdl = rgb[..., ::-1].copy() if fmt == "BMP" else rgb.copy()  # BMP surfaces are BGR
            sdl_amask = False
    return DecodedImage(rgba=rgba, has_alpha=has_alpha, sdl=sdl, sdl_alpha_mask=sdl_amask)


def _raw_gray_pgm(path: Path, max_pixels: int | None) -> DecodedImage | None:
    """A binary 8-bit PGM (what map_saver and we write) read straight from its bytes, as Pillow decodes
    it: the pixels are the bytes after the header. Pillow's decode held three copies of a 100 M-cell
    map at once (its image, the chunks it joins, the joined bytes). None for any other file, and for
    one too short for its header's size (Pillow says how it is truncated)."""
    from PIL import Image

    layout = gray_pgm_layout(path)
    if layout is None:
        return None
    width, height, offset = layout
    if max_pixels is not None:
        check_decode(path, (width, height), "L", False, max_pixels)
    if path.stat().st_size < offset + width * height:
        return None
    try:
        opened = Image.open(path)  # the header only: Pillow must read the size the grammar read
    except Image.DecompressionBombError:
        return None  # the general way says why
    with opened as im:
        check_agrees(path, header_size(path), im.size)
        if im.mode != "L":
            return None
    pixels = np.fromfile(path, dtype=np.uint8, count=width * height, offset=offset)
    sdl = pixels.reshape(height, width, 1)
    return DecodedImage(rgba=None, has_alpha=False, sdl=sdl, sdl_alpha_mask=False, spent_by_reading=True)


def image_to_data(
    img: DecodedImage,
    *,
    reader: str,
    mode: str,
    negate: bool,
    occupied_thresh: float,
    free_thresh: float,
    bottom_up: bool = False,
) -> np.ndarray:
    """Occupancy values (int8) exactly as ``reader`` computes them, in image row order (row 0 = top), or
    the grid's (row 0 = bottom) with ``bottom_up``: a big gray map is looked up in that order, not
    flipped after (a second copy of a 100 M-cell grid)."""
    gray = _plain_gray(img)
    if gray is not None:  # one value per pixel: the reader's answer for each of the 256 grays, looked up
        table = _by_value(reader, mode, negate, occupied_thresh, free_thresh)
        if img.spent_by_reading and gray.flags.c_contiguous and gray.flags.writeable:
            return _looked_up_in_place(table, gray, bottom_up)
        return np.asarray(table[gray[::-1] if bottom_up else gray])
    out = _read(img, reader=reader, mode=mode, negate=negate, occupied_thresh=occupied_thresh, free_thresh=free_thresh)
    return np.ascontiguousarray(out[::-1]) if bottom_up else out


def _read(
    img: DecodedImage, *, reader: str, mode: str, negate: bool, occupied_thresh: float, free_thresh: float
) -> np.ndarray:
    if reader == "ros1":
        return _ros1(img, mode, negate, occupied_thresh, free_thresh)
    if reader == "nav2_humble":
        return _nav2_humble(img, mode, negate, occupied_thresh, free_thresh)
    if reader == "nav2_jazzy":
        return _nav2_jazzy(img, mode, negate, occupied_thresh, free_thresh)
    raise ValueError(f"unknown map reader {reader!r}; use one of {', '.join(READERS)}")


LOOKUP_MIN_PIXELS = 65536  # below this the readers' own maths is as quick as a lookup
WRITE_CHUNK_CELLS = 65536  # cells turned into image bytes at once while writing


def _looked_up_in_place(table: np.ndarray, gray: np.ndarray, bottom_up: bool) -> np.ndarray:
    """``table[gray]`` written over ``gray`` itself, a few rows at a time (an index array of the whole
    map would be eight bytes a pixel), rows then swapped in place for ``bottom_up``."""
    out = gray.view(np.int8)
    table = table.astype(np.int8, copy=False)
    step = max(1, WRITE_CHUNK_CELLS // max(1, gray.shape[1]))
    for r in range(0, gray.shape[0], step):
        # np.take (buffered, as its output is its input) looks up in less than half the time of table[...]
        np.take(table, gray[r : r + step], out=out[r : r + step])
    if bottom_up:
        spare = np.empty(out.shape[1], dtype=np.int8)
        h = out.shape[0]
        for r in range(h // 2):
            spare[:] = out[r]
            out[r] = out[h - 1 - r]
            out[h - 1 - r] = spare
    return out


def _plain_gray(img: DecodedImage) -> np.ndarray | None:
    """The (H, W) gray values when every reader sees one opaque gray per pixel (8-bit gray files,
    by far the most common maps), else None. Big maps only."""
    if img.gray_only and img.sdl[..., 0].size >= LOOKUP_MIN_PIXELS:
        return img.sdl[..., 0]
    if img.has_alpha or img.sdl_alpha_mask or img.sdl.shape[2] != 1 or img.sdl[..., 0].size < LOOKUP_MIN_PIXELS:
        return None
    gray = img.sdl[..., 0]
    rgba = np.ascontiguousarray(img.rgba).view("<u4")[..., 0]  # r | g << 8 | b << 16 | a << 24
    return gray if np.array_equal(rgba, gray.astype("<u4") * 0x010101 + 0xFF000000) else None


def _by_value(reader: str, mode: str, negate: bool, occupied_thresh: float, free_thresh: float) -> np.ndarray:
    """The reader's output for the grays 0..255 (the same functions, on a 1x256 image): a lookup table."""
    values = np.arange(256, dtype=np.uint8)[None, :]
    rgba = np.stack([values, values, values, np.full_like(values, 255)], axis=2)
    ramp = DecodedImage(rgba=rgba, has_alpha=False, sdl=values[..., None].copy(), sdl_alpha_mask=False)
    out = image_to_data(
        ramp, reader=reader, mode=mode, negate=negate, occupied_thresh=occupied_thresh, free_thresh=free_thresh
    )
    return np.asarray(out[0])


def _ros1(img: DecodedImage, mode: str, negate: bool, occ_th: float, free_th: float) -> np.ndarray:
    px = img.sdl.astype(np.int64)
    n = px.shape[2]
    avg_n = n if (mode == "trinary" or not img.sdl_alpha_mask) else n - 1
    color_avg: np.ndarray = px[..., :avg_n].sum(axis=2) / float(avg_n)
    alpha = np.ones(px.shape[:2], dtype=np.int64) if n == 1 else px[..., n - 1]
    if negate:
        color_avg = 255 - color_avg
    if mode == "raw":  # unsigned char value = color_avg; stored as the same byte in int8 data
        raw: np.ndarray = np.trunc(color_avg).astype(np.uint8).view(np.int8)
        return raw
    occ = (255 - color_avg) / 255.0
    out = np.full(occ.shape, -1, dtype=np.int16)
    between = ~(occ > occ_th) & ~(occ < free_th)
    if mode == "scale":
        ratio = (occ - free_th) / (occ_th - free_th)
        scaled = np.trunc(1 + 98 * ratio).astype(np.int16)
        out = np.where(between & ~(alpha < 1), scaled, out)
    out = np.where(occ < free_th, 0, out)
    out = np.where(occ > occ_th, 100, out)
    return out.astype(np.int8)


def _nav2_humble(img: DecodedImage, mode: str, negate: bool, occ_th: float, free_th: float) -> np.ndarray:
    q = img.rgba.astype(np.float64) * 257.0  # 8-bit samples as GraphicsMagick Q16 quantums
    channels = [q[..., 0], q[..., 1], q[..., 2]]
    if mode == "trinary" and img.has_alpha:
        channels.append(q[..., 3])  # MaxRGB - opacity == alpha
    total = np.zeros(q.shape[:2], dtype=np.float64)
    for c in channels:
        total = total + c
    shade = (total / len(channels)) / 65535.0
    occ = shade if negate else 1.0 - shade
    out = np.full(shade.shape, -1, dtype=np.int16)
    if mode == "trinary":
        out = np.where(occ < free_th, 0, out)
        out = np.where(occ_th < occ, 100, out)
    elif mode == "scale":
        scaled = np.rint((occ - free_th) / (occ_th - free_th) * 100.0)
        out = scaled.astype(np.int16)
        out = np.where(occ < free_th, 0, out)
        out = np.where(occ_th < occ, 100, out)
        out = np.where(img.rgba[..., 3] != 255, -1, out)  # alphaQuantum != OpaqueOpacity
    elif mode == "raw":
        pct = np.floor(shade * 255 + 0.5)  # std::round: half away from zero (values are >= 0)
        out = np.where((pct >= 0) & (pct <= 100), pct, -1).astype(np.int16)
    else:
        raise ValueError(f"invalid map mode {mode!r}")
    return out.astype(np.int8)


def luma8(rgba: np.ndarray) -> np.ndarray:
    """GraphicsMagick GrayscaleType conversion to 8 bits (Rec.601 luma, rounded)."""
    rgb = rgba[..., :3].astype(np.float64)
    if np.array_equal(rgb[..., 0], rgb[..., 1]) and np.array_equal(rgb[..., 1], rgb[..., 2]):
        return rgba[..., 0].astype(np.uint8)
    y = 0.299 * rgb[..., 0] + 0.587 * rgb[..., 1] + 0.114 * rgb[..., 2]
    return np.floor(y + 0.5).clip(0, 255).astype(np.uint8)


def _nav2_jazzy(img: DecodedImage, mode: str, negate: bool, occ_th: float, free_th: float) -> np.ndarray:
    gray = luma8(img.rgba)
    if mode == "raw":
        signed = gray.view(np.int8).astype(np.int16)
        return np.where((signed >= 0) & (signed <= 100), signed, -1).astype(np.int8)
    if mode not in ("trinary", "scale"):
        raise ValueError(f"invalid map mode {mode!r}")
    f32 = np.float32
    norm = gray.astype(f32) / f32(255.0)
    if not negate:
        norm = f32(1.0) - norm
    occ_f, free_f = f32(occ_th), f32(free_th)
    out = np.full(gray.shape, -1, dtype=np.int16)
    out = np.where(norm >= occ_f, 100, out)
    out = np.where(norm <= free_f, 0, out)
    if mode == "scale":
        between = (norm > free_f) & (norm < occ_f)
        scaled = ((norm - free_f) / (occ_f - free_f)) * f32(100.0)
        rounded = np.sign(scaled) * np.floor(np.abs(scaled) + f32(0.5))  # Eigen round: half away
        out = np.where(between, rounded.astype(np.int16), out)
    if img.has_alpha:
        out = np.where(img.rgba[..., 3] < 255, -1, out)
    return out.astype(np.int8)


def grid_to_gray(grid: OccupancyGrid | np.ndarray) -> np.ndarray:
    """Image bytes for a grid: uint8 (H, W), image row 0 = top.

    -1 (and anything outside 0..100) -> 205, 0 -> 254, 100 -> 0, 1..99 -> rint((100 - v) * 254 / 100)
    like a scale-mode map_saver image, so probabilities survive as shades of gray.
    """
    data = grid.data if isinstance(grid, OccupancyGrid) else np.asarray(grid)
    # a 256-entry lookup on the raw bytes keeps memory at one byte per cell for huge grids
    return np.ascontiguousarray(_GRAY_LUT[data.astype(np.int8, copy=False).view(np.uint8)][::-1])


def pgm_bytes(gray: np.ndarray) -> bytes:
    """Binary 8-bit PGM (P5, maxval 255): the format map_saver writes by default."""
    h, w = gray.shape
    return f"P5\n{w} {h}\n255\n".encode("ascii") + np.ascontiguousarray(gray, dtype=np.uint8).tobytes()


def write_pgm(grid: OccupancyGrid, fh: BinaryIO, rows_per_chunk: int | None = None) -> None:
    """Stream ``grid`` as a P5 PGM (same bytes as ``pgm_bytes(grid_to_gray(grid))``) in row chunks of
    about 64 Ki cells, so no grid, large or small, needs a second full-size copy in memory."""
    fh.write(f"P5\n{grid.width} {grid.height}\n255\n".encode("ascii"))
    data = grid.data.view(np.uint8)
    rows_per_chunk = rows_per_chunk or max(1, WRITE_CHUNK_CELLS // max(1, grid.width))
    for stop in range(grid.height, 0, -rows_per_chunk):
        start = max(0, stop - rows_per_chunk)
        fh.write(np.ascontiguousarray(_GRAY_LUT[data[start:stop][::-1]]).data)


def preview_image(grid: OccupancyGrid, px_per_m: float, max_side: int) -> tuple[np.ndarray, float]:
    """Nearest-neighbour gray preview at ``px_per_m`` (capped so the longest side <= max_side).

    Returns (gray uint8 image with row 0 = top, the px_per_m actually used along x).
    """
    width_m, height_m = grid.size_m
    scale = px_per_m
    longest = max(width_m, height_m) * scale
    if longest > max_side:
        scale = max_side / max(width_m, height_m)
    pw = max(1, round(width_m * scale))
    ph = max(1, round(height_m * scale))
    cols = np.minimum(((np.arange(pw) + 0.5) * grid.width / pw).astype(np.int64), grid.width - 1)
    rows = np.minimum(((np.arange(ph) + 0.5) * grid.height / ph).astype(np.int64), grid.height - 1)
    picked = grid.data[np.ix_(grid.height - 1 - rows, cols)]  # image row 0 = top = last grid row
    return np.ascontiguousarray(_GRAY_LUT[picked.view(np.uint8)]), pw / width_m
