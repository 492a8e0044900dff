"""The maps folder (``ALMA_MAPS``): building plans in, map sets out.

``convert`` is the one plan -> map files pipeline (:func:`convert_plan`, used by ``pmk convert``, the
Maps screen and notebook 01); ``folder`` holds :class:`MapsFolder` (list, import, download, convert,
delete); ``scan`` reads the generated map sets back, ``info`` the storeys of a plan, ``download``
fetches a plan from a URL and ``naming`` is the one rule for generated file names.
"""

from __future__ import annotations

from pmk_nb.library.convert import ConvertOptions, ConvertResult, StoreyMap, convert_plan
from pmk_nb.library.folder import MapEntry, MapsFolder, check_name, default_maps_dir
from pmk_nb.library.info import StoreyInfo
from pmk_nb.library.naming import safe_file_part, storey_map_names
from pmk_nb.library.scan import GeneratedMap

__all__ = [
    "ConvertOptions",
    "ConvertResult",
    "GeneratedMap",
    "MapEntry",
    "MapsFolder",
    "StoreyInfo",
    "StoreyMap",
    "check_name",
    "convert_plan",
    "default_maps_dir",
    "safe_file_part",
    "storey_map_names",
]
