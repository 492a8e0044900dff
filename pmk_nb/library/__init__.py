"""The maps folder (``ALMA_MAPS``): building plans in, map sets out.

``folder`` holds :class:`MapsFolder` (list, import, download, convert, delete); ``scan`` reads the
generated map sets back, ``info`` the storeys of a plan, ``download`` fetches a plan from a URL and
``naming`` is the one rule for generated file names.
"""

from __future__ import annotations

from pmk_nb.library.folder import MapEntry, MapsFolder, check_name, default_maps_dir
from pmk_nb.library.info import StoreyInfo
from pmk_nb.library.naming import safe_file_part, storey_map_names
from pmk_nb.library.scan import GeneratedMap

__all__ = [
    "GeneratedMap",
    "MapEntry",
    "MapsFolder",
    "StoreyInfo",
    "check_name",
    "default_maps_dir",
    "safe_file_part",
    "storey_map_names",
]
