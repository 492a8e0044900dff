"""Map catalogues (issue 27): publish the maps folder as a static STAC catalogue, browse one, install from it.

``publish`` writes ``SITE/catalog.json``, a Collection per building and an Item per storey with
checksummed assets (``stacdocs`` builds the documents, ``hashes`` the ``file:checksum`` multihash,
``geo`` the footprint of a georeferenced plan); ``remote`` reads a catalogue over http(s) through
the library's guarded downloader, keeping every link inside the catalogue's folder; ``install``
downloads a building's files, checks each size and SHA-256 and swaps them all into the maps folder
at once; ``state`` keeps the catalogue URLs (settings) and what was installed from where.
"""

from __future__ import annotations

__all__ = ["install", "publish", "remote", "state"]
