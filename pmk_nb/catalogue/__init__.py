"""Map catalogues (issue 27): publish the maps folder as a static STAC catalogue, browse one, install from it.

``publish`` writes ``SITE/catalog.json``, a Collection per building and an Item per storey with
checksummed assets (``stacdocs`` builds the documents, ``hashes`` the ``file:checksum`` multihash,
``geo`` the footprint of a georeferenced plan); ``remote`` reads a catalogue over http(s) through
the library's guarded downloader, keeping every link inside the catalogue's folder; ``install``
downloads a building's files, checks each size and SHA-256 and swaps them all into the maps folder
at once; ``state`` keeps the catalogue URLs (settings) and what was installed from where.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.catalogue.install import InstallResult
    from pmk_nb.catalogue.remote import Building, Catalogue, Reader, read_catalogue
    from pmk_nb.catalogue.state import CHANGED, INSTALLED, NEW, CatalogueSources, InstallRecord, read_json_object

_WHERE = {
    "InstallResult": "install",
    "Building": "remote",
    "Catalogue": "remote",
    "Reader": "remote",
    "read_catalogue": "remote",
    "CHANGED": "state",
    "CatalogueSources": "state",
    "INSTALLED": "state",
    "InstallRecord": "state",
    "NEW": "state",
    "read_json_object": "state",
}

__all__ = [
    "CHANGED",
    "INSTALLED",
    "NEW",
    "Building",
    "Catalogue",
    "CatalogueSources",
    "InstallRecord",
    "InstallResult",
    "Reader",
    "install",
    "publish",
    "read_catalogue",
    "read_json_object",
    "remote",
    "state",
]


__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
