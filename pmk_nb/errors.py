"""Error hierarchy shared by every layer.

Each layer raises its own subclass so callers (CLI, widgets) can catch ``PmkError`` once and
show ``str(err)``: messages name the file / element / host at fault and what the user can do.
"""

from __future__ import annotations


class PmkError(Exception):
    """Base of every error PMK Notebook raises on purpose."""


class IndoorGMLError(PmkError):
    """An IndoorGML file cannot be read or makes no sense as a building."""


class OccupancyError(PmkError):
    """A storey cannot be rasterised (e.g. the grid would exceed the memory budget)."""


class MapFormatError(PmkError):
    """A map_server YAML or image file is missing, malformed or unsupported."""


class LibraryError(PmkError):
    """A maps-folder operation failed (download, import, convert, delete)."""


class ChairLinkError(PmkError):
    """The rosbridge connection to a chair failed or a chair service misbehaved."""


class TransferError(PmkError):
    """Copying a map to the chair over SFTP failed."""


class DeployError(PmkError):
    """Sending, reloading or confirming a map on the chair failed."""


class SettingsError(PmkError):
    """A chair profile holds an invalid value."""
