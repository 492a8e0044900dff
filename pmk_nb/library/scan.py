"""Find the generated maps in the maps folder and tell which IndoorGML source each belongs to.

A map YAML names its source in the extras :class:`~pmk_nb.library.folder.MapsFolder` writes (``map``,
``source``, ``storey``, ``source_sha256``); maps made elsewhere are matched by the original naming,
``NAME.yaml`` or ``NAME_<storey>.yaml``. A YAML that cannot be read is still listed, marked broken
with the reason, so one corrupt file never hides the others.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from pmk_nb.errors import MapFormatError


@dataclass
class GeneratedMap:
    """One map_server map (YAML + image + optional preview) generated from a source.

    ``broken`` holds the reason when the YAML or its image cannot be read (then resolution, width
    and height are 0); ``stale`` is True when the source changed since the map was generated;
    ``tagged`` is False for maps matched only by file name, which the folder never deletes on its own.
    """

    storey: str | None
    yaml: Path
    image: Path
    preview: Path | None
    resolution: float
    width: int
    height: int
    source_sha256: str = ""
    stale: bool = False
    broken: str = ""
    tagged: bool = False  # the YAML names its map/source (written by MapsFolder.convert)

    @property
    def ok(self) -> bool:
        return not self.broken


def scan_generated(root: Path, sources: dict[str, Path]) -> dict[str, list[GeneratedMap]]:
    """Generated maps in ``root`` keyed by source name ("" for maps that belong to no source)."""
    found: dict[str, list[GeneratedMap]] = {}
    if not root.is_dir():
        return found
    by_file = {p.name: n for n, p in sources.items()}
    for path in sorted(root.iterdir()):
        if path.name.startswith(".") or path.suffix.lower() not in (".yaml", ".yml") or not path.is_file():
            continue
        owner, gm = _read_one(path, sources, by_file)
        found.setdefault(owner, []).append(gm)
    for maps in found.values():
        maps.sort(key=lambda g: (g.storey or "", g.yaml.name))
    return found


def _owner_by_name(stem: str, sources: dict[str, Path]) -> tuple[str, str | None]:
    if stem in sources:
        return stem, None
    best = max((n for n in sources if stem.startswith(n + "_")), key=len, default="")
    return (best, stem[len(best) + 1 :]) if best else ("", None)


def _read_one(path: Path, sources: dict[str, Path], by_file: dict[str, str]) -> tuple[str, GeneratedMap]:
    from pmk_nb.rosmap import read_map_yaml

    owner, storey = _owner_by_name(path.stem, sources)
    try:
        info = read_map_yaml(path)
    except MapFormatError as err:
        guess = next((p for p in (path.with_suffix(".pgm"), path.with_suffix(".png")) if p.exists()), None)
        preview = path.with_name(f"{path.stem}-visualization.png")
        return owner, GeneratedMap(
            storey=storey,
            yaml=path,
            image=guess or path.with_suffix(".pgm"),
            preview=preview if preview.exists() else None,
            resolution=0.0,
            width=0,
            height=0,
            broken=str(err),
        )
    extras = info.extras
    named = str(extras.get("map", ""))
    source_file = Path(str(extras.get("source", ""))).name
    tagged = True
    if named in sources:
        owner = named
    elif source_file in by_file:
        owner = by_file[source_file]
    else:
        tagged = False
    if "storey" in extras and extras["storey"] is not None:
        storey = str(extras["storey"])
    preview_name = extras.get("preview") or f"{path.stem}-visualization.png"
    preview = path.parent / Path(str(preview_name)).name
    width, height, broken = _image_size(info.image)
    return owner, GeneratedMap(
        storey=storey,
        yaml=path,
        image=info.image,
        preview=preview if preview.is_file() else None,
        resolution=info.resolution,
        width=width,
        height=height,
        source_sha256=str(extras.get("source_sha256") or ""),
        broken=broken,
        tagged=tagged,
    )


def _image_size(image: Path) -> tuple[int, int, str]:
    """(width, height, "") from the image header, or (0, 0, reason)."""
    from PIL import Image, UnidentifiedImageError

    from pmk_nb.errors import MalformedImageHeader
    from pmk_nb.rosmap import header_size

    try:
        size = header_size(image)
        if size is None:
            with Image.open(image) as im:
                size = im.size
        width, height = size
    except FileNotFoundError:
        return 0, 0, f"image file {image} is missing"
    except MalformedImageHeader as err:
        return 0, 0, str(err)
    except (OSError, UnidentifiedImageError, ValueError) as err:
        return 0, 0, f"cannot read image {image}: {err}"
    return int(width), int(height), ""
