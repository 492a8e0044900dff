"""ROS map_server files: write and read ``NAME.yaml`` + image exactly as ROS 1 map_server and Nav2 do.

``files`` is the YAML + image pair (read, write, the map set on disk); ``image`` decodes and encodes
the image itself (PGM/PNG/BMP, trinary/scale/raw, the three map server readers, ``READERS``); ``header`` reads an
image's size by its format's grammar, ``guard`` confines files and prices decoding against the pixel cap.
"""

from __future__ import annotations

from pmk_nb.rosmap.files import (
    INVALID_MAP_DATA,
    INVALID_MAP_METADATA,
    MAP_DOES_NOT_EXIST,
    NAV2_MAX_CELLS_PER_SIDE,
    MapFiles,
    MapLoadError,
    MapYaml,
    read_map,
    read_map_yaml,
    write_map,
)
from pmk_nb.rosmap.header import header_size
from pmk_nb.rosmap.image import READERS, ImageReader, grid_to_gray

__all__ = [
    "INVALID_MAP_DATA",
    "INVALID_MAP_METADATA",
    "MAP_DOES_NOT_EXIST",
    "NAV2_MAX_CELLS_PER_SIDE",
    "READERS",
    "ImageReader",
    "MapFiles",
    "MapLoadError",
    "MapYaml",
    "grid_to_gray",
    "header_size",
    "read_map",
    "read_map_yaml",
    "write_map",
]
