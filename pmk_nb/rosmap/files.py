"""Read and write ROS map_server maps (YAML + PGM/PNG/BMP), exactly as ROS 1 and Nav2 do.

The reader mirrors ``map_server`` (ROS 1) and ``nav2_map_server/map_io`` (Humble; Jazzy's Eigen
rewrite): pixel rules live in :mod:`pmk_nb.rosmap.image`. Errors carry Nav2's ``LoadMap`` result
codes (``code`` attribute) so the simulator and the UI can report what a real map server would.

The writer emits the one encoding every loader reads alike (8-bit P5 PGM, 0 / 254 / 205, no alpha,
``negate: 0``, ``occupied_thresh: 0.65``, ``free_thresh: 0.196``, ``mode: trinary``) plus a
``NAME-visualization.png`` preview, and replaces the whole set atomically.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pmk_nb import __version__
from pmk_nb.defaults import NAV2_MAX_CELLS_PER_SIDE as NAV2_MAX_CELLS_PER_SIDE  # declared there, re-exported
from pmk_nb.errors import INVALID_MAP_DATA as INVALID_MAP_DATA  # the Nav2 codes and error: re-exported
from pmk_nb.errors import INVALID_MAP_METADATA as INVALID_MAP_METADATA
from pmk_nb.errors import MAP_DOES_NOT_EXIST as MAP_DOES_NOT_EXIST
from pmk_nb.errors import MapFormatError
from pmk_nb.errors import MapLoadError as MapLoadError
from pmk_nb.fileio import Content, Writer, replace_all
from pmk_nb.grid import OccupancyGrid, nice_ceil
from pmk_nb.rosmap.guard import confine, pixel_cap
from pmk_nb.rosmap.image import (
    MODES,
    READERS,
    ImageReader,
    decode_image,
    grid_to_gray,
    image_to_data,
    preview_image,
    write_pgm,
)

PREVIEW_MAX_SIDE = 4096
OCCUPIED_THRESH = 0.65
FREE_THRESH = 0.196
_STANDARD_KEYS = ("image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode")


@dataclass
class MapYaml:
    """The fields of a map_server YAML file: THE reader every module uses (simulator, deploy, transfer).

    Attributes:
        path: the YAML file.
        image: the image path resolved against the YAML's folder (what a map server opens).
        image_text: the ``image`` entry exactly as written in the YAML.
        extras: every key that is not a standard map_server key (our ``storey``, ``source`` ...).
    """

    path: Path
    image: Path
    resolution: float
    origin: tuple[float, float, float]
    negate: bool
    occupied_thresh: float
    free_thresh: float
    mode: str = "trinary"
    extras: dict[str, Any] = field(default_factory=dict)
    image_text: str = ""

    @property
    def image_is_beside(self) -> bool:
        """True when the image is a plain file in the YAML's own folder (no ``..``, no symlink out of it).

        The ``..`` rule reads the YAML's own ``image`` text: a ``..`` in the path the YAML was opened by
        (``maps/../maps/clinic.yaml``) says nothing about where its image is (issue 40).
        """
        written = Path(self.image_text) if self.image_text else self.image
        lexically = Path(os.path.abspath(self.image)).parent == Path(os.path.abspath(self.path)).parent
        return ".." not in written.parts and lexically and self.image.resolve().parent == self.path.resolve().parent

    def fields(self, *, image: str | None = None) -> dict[str, Any]:
        """The YAML as a mapping (standard keys first, then the extras), ``image`` replaced if given."""
        return {
            "image": self.image_text if image is None else image,
            "resolution": self.resolution,
            "origin": list(self.origin),
            "negate": int(self.negate),
            "occupied_thresh": self.occupied_thresh,
            "free_thresh": self.free_thresh,
            "mode": self.mode,
            **self.extras,
        }


@dataclass
class MapFiles:
    """The files of one written map: what gets sent to the chair (+ the preview for the screen)."""

    yaml: Path
    image: Path
    preview: Path | None


def _meta_error(path: Path | str, reason: str) -> MapLoadError:
    return MapLoadError(f"{path}: invalid map YAML: {reason}", INVALID_MAP_METADATA, path=str(path))


def _number(doc: dict[str, Any], key: str, path: Path) -> float:
    if key not in doc:
        raise _meta_error(path, f"missing required key '{key}'")
    value = doc[key]
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise _meta_error(path, f"'{key}' must be a number, got {value!r}")
    if not math.isfinite(float(value)):
        raise _meta_error(path, f"'{key}' must be finite, got {value!r}")
    return float(value)


def read_map_yaml(yaml_path: str | Path) -> MapYaml:
    """Parse a map_server YAML file as both ROS 1 and Nav2 would (they accept the same keys).

    Raises:
        MapLoadError: code 1 for an empty path, 3 for a missing or unparsable file or field.
    """
    import yaml

    if not str(yaml_path):
        raise MapLoadError("map YAML path is empty", MAP_DOES_NOT_EXIST)
    path = Path(yaml_path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError as err:
        raise _meta_error(path, "file not found") from err
    except (OSError, UnicodeDecodeError) as err:
        raise _meta_error(path, f"cannot read file ({err})") from err
    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError as err:
        raise _meta_error(path, f"not valid YAML ({err})") from err
    if not isinstance(doc, dict):
        raise _meta_error(path, "expected a mapping of keys (image, resolution, origin, ...)")
    image = doc.get("image")
    if not isinstance(image, str) or not image:
        raise _meta_error(path, "'image' must name the image file")
    resolution = _number(doc, "resolution", path)
    if resolution <= 0:
        raise _meta_error(path, f"'resolution' must be positive, got {resolution}")
    origin = doc.get("origin")
    if not isinstance(origin, list) or len(origin) != 3:
        raise _meta_error(path, f"'origin' must be a list of 3 numbers [x, y, yaw], got {origin!r}")
    origin_doc = {f"origin[{i}]": v for i, v in enumerate(origin)}
    origin_vals = [_number(origin_doc, f"origin[{i}]", path) for i in range(3)]
    occ = _number(doc, "occupied_thresh", path)
    free = _number(doc, "free_thresh", path)
    if "negate" not in doc:
        raise _meta_error(path, "missing required key 'negate'")
    negate = doc["negate"]
    if not isinstance(negate, int):  # bool is an int; Nav2 also accepts true/false
        raise _meta_error(path, f"'negate' must be 0 or 1, got {negate!r}")
    mode = doc.get("mode", "trinary")
    if mode not in MODES:
        raise _meta_error(path, f"'mode' must be one of {', '.join(MODES)}, got {mode!r}")
    image_path = Path(image)
    if not image_path.is_absolute():
        image_path = path.parent / image_path
    extras = {k: v for k, v in doc.items() if k not in _STANDARD_KEYS}
    return MapYaml(
        path=path,
        image=image_path,
        resolution=resolution,
        origin=(origin_vals[0], origin_vals[1], origin_vals[2]),
        negate=bool(negate),
        occupied_thresh=occ,
        free_thresh=free,
        mode=mode,
        extras=extras,
        image_text=image,
    )


def read_map(
    yaml_path: str | Path, *, reader: ImageReader = "ros1", within: Path | None = None, max_pixels: int | None = None
) -> OccupancyGrid:
    """Load a map as the map server ``reader`` ("ros1", "nav2_humble", "nav2_jazzy") would publish it.

    Returns an OccupancyGrid (row 0 = bottom) whose ``meta`` holds the YAML's extra keys. ``within``
    (a map server's folder) confines the YAML and its image, symlinks followed; ``max_pixels``
    (default ``PMK_MAP_MAX_PIXELS`` or :data:`~pmk_nb.rosmap.guard.MAX_MAP_PIXELS`, in 8-bit gray
    pixels: a 16-bit or colour image gets fewer) caps the image's size as the decoder opened it,
    before it decodes a pixel.

    Raises:
        MapLoadError: code 3 for YAML problems, 2 when the image is missing or unreadable (or, for
            nav2_jazzy, wider/taller than 32767 cells); MapOutsideFolder, MapImageTooLarge,
            MalformedImageHeader.
    """
    if reader not in READERS:
        raise ValueError(f"unknown map reader {reader!r}; use one of {', '.join(READERS)}")
    if within is not None:
        confine(Path(yaml_path), within, what="YAML")
    info = read_map_yaml(yaml_path)
    if within is not None:
        confine(info.image, within, what="image", yaml=info.path)
    try:
        img = decode_image(info.image, max_pixels=pixel_cap() if max_pixels is None else max_pixels)
    except FileNotFoundError as err:
        msg = f"{info.path}: image file {info.image} not found"
        raise MapLoadError(msg, INVALID_MAP_DATA, path=str(info.image)) from err
    except MapLoadError:
        raise
    except Exception as err:  # Pillow raises many types for corrupt files
        msg = f"{info.path}: cannot read image {info.image}: {err}"
        raise MapLoadError(msg, INVALID_MAP_DATA, path=str(info.image)) from err
    height, width = img.size
    if reader == "nav2_jazzy" and max(width, height) > NAV2_MAX_CELLS_PER_SIDE:
        raise MapLoadError(
            f"{info.image}: {width}x{height} pixels; Nav2 Jazzy+ rejects maps wider or taller than "
            f"{NAV2_MAX_CELLS_PER_SIDE} cells",
            INVALID_MAP_DATA,
            path=str(info.image),
        )
    data = image_to_data(
        img,
        reader=reader,
        mode=info.mode,
        negate=info.negate,
        occupied_thresh=info.occupied_thresh,
        free_thresh=info.free_thresh,
        bottom_up=True,
    )
    return OccupancyGrid(
        data=data,
        resolution=info.resolution,
        origin=info.origin,
        frame_id="map",
        meta=dict(info.extras),
    )


def suggest_resolution(resolution: float, cells: int, limit: int) -> float:
    """The coarser resolution (rounded up to 2 significant digits) that brings ``cells`` <= limit."""
    return nice_ceil(resolution * cells / limit)


def _plain(value: Any) -> Any:
    """YAML-safe plain Python value (tuples -> lists, numpy scalars -> Python numbers)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    if value is None or isinstance(value, str | int | float | bool):
        return value
    return str(value)


def _yaml_text(grid: OccupancyGrid, image_name: str, extras: dict[str, Any]) -> str:
    import yaml

    doc: dict[str, Any] = {
        "image": image_name,
        "resolution": float(grid.resolution),
        "origin": [float(grid.origin[0]), float(grid.origin[1]), 0.0],
        "negate": 0,
        "occupied_thresh": OCCUPIED_THRESH,
        "free_thresh": FREE_THRESH,
        "mode": "trinary",
    }
    for key, value in extras.items():
        if key not in doc:
            doc[key] = _plain(value)
    # PyYAML writes floats with repr(), so every value reads back bit-for-bit
    return yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, allow_unicode=True)


def _png_writer(gray: np.ndarray) -> Writer:
    """Writes ``gray`` as a PNG straight into the file (no bytes copy of the encoded image)."""
    from PIL import Image

    image = Image.fromarray(np.ascontiguousarray(gray, dtype=np.uint8), mode="L")
    return lambda fh: image.save(fh, format="PNG")


def write_map(
    grid: OccupancyGrid,
    directory: str | Path,
    name: str,
    *,
    image_format: str = "pgm",
    preview: bool = True,
    preview_px_per_m: float = 10.0,
    allow_large: bool = False,
) -> MapFiles:
    """Write NAME.yaml + NAME.pgm|png (+ NAME-visualization.png) into ``directory``, atomically.

    Every file is first written to a temporary file in ``directory``; only when all succeeded are
    they renamed into place (image first, YAML last), so a failure leaves the previous set untouched.

    Raises:
        MapFormatError: bad name/format, grid wider or taller than 32767 cells (unless
            ``allow_large``), or the files cannot be written.
    """
    image_format = image_format.lower()
    if image_format not in ("pgm", "png"):
        raise MapFormatError(f"image format must be 'pgm' or 'png', got {image_format!r}")
    if not name or "/" in name or "\\" in name or name in (".", ".."):
        raise MapFormatError(f"invalid map name {name!r}: use a plain file name without folders")
    longest = max(grid.width, grid.height)
    if longest > NAV2_MAX_CELLS_PER_SIDE and not allow_large:
        fit = suggest_resolution(grid.resolution, longest, NAV2_MAX_CELLS_PER_SIDE)
        raise MapFormatError(
            f"map {name!r} is {grid.width} x {grid.height} cells at {grid.resolution} m/cell; Nav2 "
            f"(Jazzy and later) rejects maps wider or taller than {NAV2_MAX_CELLS_PER_SIDE} cells. "
            f"Use a resolution of {fit} m or coarser."
        )
    if not (math.isfinite(grid.origin[0]) and math.isfinite(grid.origin[1])):
        raise MapFormatError(f"map {name!r}: origin {grid.origin[:2]} is not finite")
    folder = Path(directory)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise MapFormatError(f"cannot create map folder {folder}: {err}", path=str(folder)) from err

    image_name = f"{name}.{image_format}"
    preview_name = f"{name}-visualization.png"
    contents: list[tuple[str, Content]] = []
    if image_format == "pgm":
        contents.append((image_name, lambda fh: write_pgm(grid, fh)))
    else:
        contents.append((image_name, _png_writer(grid_to_gray(grid))))
    # facts about this file set are ours to state; None values are left out of the YAML
    extras = {k: v for k, v in grid.meta.items() if v is not None and k not in ("preview", "preview_px_per_m")}
    extras["generator"] = f"pmk_nb {__version__}"
    if preview:
        pv, used_px_per_m = preview_image(grid, preview_px_per_m, PREVIEW_MAX_SIDE)
        contents.append((preview_name, _png_writer(pv)))
        del pv  # the writer holds the image
        extras["preview"] = preview_name
        extras["preview_px_per_m"] = float(used_px_per_m)
    contents.append((f"{name}.yaml", _yaml_text(grid, image_name, extras)))
    try:
        replace_all(folder, contents)
    except IsADirectoryError as err:
        raise MapFormatError(f"cannot write {err.filename}: a folder has that name", path=err.filename) from err
    except OSError as err:
        raise MapFormatError(f"cannot write map files in {folder}: {err}", path=str(folder)) from err
    return MapFiles(
        yaml=folder / f"{name}.yaml",
        image=folder / image_name,
        preview=folder / preview_name if preview else None,
    )
