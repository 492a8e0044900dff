"""The maps folder (``ALMA_MAPS``): building plans in, map sets out.

``convert`` is the one plan -> map files pipeline (:func:`convert_plan`, used by ``pmk convert``, the
Maps screen and notebook 01); ``folder`` holds :class:`MapsFolder` (list, import, download, convert,
delete); ``scan`` reads the generated map sets back, ``info`` the storeys of a plan, ``download``
fetches a plan from a URL and ``naming`` is the one rule for generated file names.

The names below are imported on first use, so ``pmk convert`` (which needs ``convert`` only) does not
pay for the maps folder and the downloader's HTTP, TLS and e-mail modules (issue 31: a small plan's
whole convert in 0.5 s).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.library.choices import ConvertChoices, last_choices, offered, window_cells
    from pmk_nb.library.convert import ConvertOptions, ConvertResult, StoreyMap, convert_plan
    from pmk_nb.library.download import check_url, fetch
    from pmk_nb.library.folder import MapEntry, MapsFolder, check_name, default_maps_dir
    from pmk_nb.library.info import LayerOption, StoreyInfo
    from pmk_nb.library.naming import SOURCE_SUFFIXES, safe_file_part, storey_map_names
    from pmk_nb.library.netguard import ALLOW_LOCAL_ENV
    from pmk_nb.library.scan import GeneratedMap

_WHERE = {
    "ConvertChoices": "choices",
    "last_choices": "choices",
    "offered": "choices",
    "window_cells": "choices",
    "ConvertOptions": "convert",
    "ConvertResult": "convert",
    "StoreyMap": "convert",
    "convert_plan": "convert",
    "check_url": "download",
    "fetch": "download",
    "MapEntry": "folder",
    "MapsFolder": "folder",
    "check_name": "folder",
    "default_maps_dir": "folder",
    "LayerOption": "info",
    "StoreyInfo": "info",
    "SOURCE_SUFFIXES": "naming",
    "safe_file_part": "naming",
    "storey_map_names": "naming",
    "ALLOW_LOCAL_ENV": "netguard",
    "GeneratedMap": "scan",
}

__all__ = [
    "ALLOW_LOCAL_ENV",
    "SOURCE_SUFFIXES",
    "ConvertChoices",
    "ConvertOptions",
    "ConvertResult",
    "GeneratedMap",
    "LayerOption",
    "MapEntry",
    "MapsFolder",
    "StoreyInfo",
    "StoreyMap",
    "check_name",
    "check_url",
    "convert_plan",
    "default_maps_dir",
    "fetch",
    "last_choices",
    "offered",
    "safe_file_part",
    "storey_map_names",
    "window_cells",
]


__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
