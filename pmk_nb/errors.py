"""Error hierarchy shared by every layer: types with fields, never text to match.

Each layer raises its own subclass with the facts a caller needs as attributes (which file, which
element, which host, which deploy step, whether the chair kept its old map). Control flow looks at
types and fields only; the text (``str(err)``) is for people and is composed by the layer that
knows the facts. Each interface (CLI, dashboard) turns an error into its own words in one place.
"""

from __future__ import annotations


class PmkError(Exception):
    """Base of every error PMK Notebook raises on purpose.

    Args:
        message: what went wrong, naming the file / element / host at fault.
        hint: what the user can do about it (optional; shown after the message).

    Attributes:
        exit_code: the `pmk` command's exit status when this error ends it (a type may say otherwise).
    """

    exit_code: int = 2

    def __init__(self, message: str, *, hint: str = "") -> None:
        super().__init__(message)
        self.message = message
        self.hint = hint

    def __str__(self) -> str:
        if not self.hint:
            return self.message
        stop = "" if self.message.rstrip().endswith((".", ":", "!", "?")) else "."
        return f"{self.message}{stop} {self.hint}"


class IndoorGMLError(PmkError):
    """An IndoorGML file cannot be read or makes no sense as a building."""

    def __init__(self, message: str, *, path: str | None = None, element: str | None = None, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.path = path
        self.element = element


class NotWellFormed(IndoorGMLError):
    """The file is not well-formed XML.

    Attributes:
        line: the line the parser stopped at (1-based), or None when it could not say.
        column: the column there, or None.
        began_as_xml: True when the file began as an XML document (a prolog and a root start tag) and
            broke later ("malformed XML"); False when it is not XML at all. Read from the file's bytes,
            never from how far the parser got, which depends on how it batches its input.
        open_elements: the elements open at the error, outermost first, as written (``gml:Polygon``).
    """

    def __init__(
        self,
        message: str,
        *,
        path: str,
        line: int | None,
        column: int | None,
        began_as_xml: bool,
        open_elements: tuple[str, ...],
        hint: str = "",
    ) -> None:
        super().__init__(message, path=path, element=open_elements[-1] if open_elements else None, hint=hint)
        self.line = line
        self.column = column
        self.began_as_xml = began_as_xml
        self.open_elements = open_elements


class UnknownLayer(IndoorGMLError):
    """``--layer NAME`` names no space layer of the file with cells to draw.

    Attributes:
        layer: the name asked for.
        known: the file's layers that can be drawn (id, and name when it has one).
    """

    def __init__(self, message: str, *, path: str, layer: str, known: list[str], hint: str = "") -> None:
        super().__init__(message, path=path, element=layer, hint=hint)
        self.layer = layer
        self.known = known


class OccupancyError(PmkError):
    """A storey cannot be rasterised."""


class GridTooLarge(OccupancyError):
    """The grid at the asked resolution would exceed the memory budget or Nav2's side limit.

    Attributes:
        cells: cells the grid would have (or its longest side, for the side limit).
        limit: the budget it exceeds.
        suggested_resolution: the finest resolution that fits, in metres per cell.
    """

    def __init__(self, message: str, *, cells: int, limit: int, suggested_resolution: float, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.cells = cells
        self.limit = limit
        self.suggested_resolution = suggested_resolution


class MapFormatError(PmkError):
    """A map_server YAML or image file is missing, malformed or unsupported."""

    def __init__(self, message: str, *, path: str | None = None, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.path = path


# nav2_msgs/srv/LoadMap result codes (what a map server answers for each failure)
MAP_DOES_NOT_EXIST = 1
INVALID_MAP_DATA = 2
INVALID_MAP_METADATA = 3


class MapNotFound(MapFormatError):
    """No map YAML at the path given (issue 29: this was reported as a missing rooms file).

    Attributes:
        name: the map asked for (the YAML's stem).
        folder: the folder it was looked for in.
        present: the maps (YAML stems) that folder does hold, sorted; empty when it holds none or is missing.
    """

    def __init__(self, path: str, *, name: str, folder: str, present: list[str]) -> None:
        there = f"maps there: {', '.join(present)}" if present else "it holds no map"
        super().__init__(
            f"no map named {name!r} in {folder} ({there})",
            path=path,
            hint="Convert the building plan first (pmk convert, pmk maps convert or MapsFolder.convert) "
            "and pass the YAML path it returns.",
        )
        self.name = name
        self.folder = folder
        self.present = present


class MapLoadError(MapFormatError):
    """A map could not be loaded; ``code`` is the Nav2 LoadMap result a map server would return."""

    def __init__(self, message: str, code: int, *, path: str | None = None, hint: str = "") -> None:
        super().__init__(message, path=path, hint=hint)
        self.code = code


class MapOutsideFolder(MapLoadError):
    """A map's YAML, or the image it names, lies outside the map server's folder (symlinks followed).

    Attributes:
        path: the file as named; folder: the folder it must be in; what: "YAML" or "image".
    """

    def __init__(self, message: str, *, path: str, folder: str, what: str) -> None:
        code = MAP_DOES_NOT_EXIST if what == "YAML" else INVALID_MAP_DATA
        super().__init__(message, code, path=path, hint="Keep the map's YAML and image inside the maps folder.")
        self.folder = folder
        self.what = what


class MapImageTooLarge(MapLoadError):
    """A map image has more pixels than a map server decodes (checked before decoding).

    Attributes:
        width, height: the size the decoder would decode (None when it refused to even open it).
        limit: the pixels of this kind of image the cap allows (the cap itself for 8-bit gray).
        mode: the decoder's pixel mode ("L", "I;16", "RGBA", ...; None when it refused to open it).
    """

    def __init__(
        self, message: str, *, path: str, width: int | None, height: int | None, limit: int, mode: str | None = None
    ) -> None:
        super().__init__(message, INVALID_MAP_DATA, path=path)
        self.width = width
        self.height = height
        self.limit = limit
        self.mode = mode


class MalformedImageHeader(MapLoadError):
    """A map image's header breaks its format's grammar (a Netpbm header read by the spec).

    Attributes:
        path: the image file; reason: what is wrong, in words.
    """

    def __init__(self, message: str, *, path: str, reason: str) -> None:
        super().__init__(message, INVALID_MAP_DATA, path=path)
        self.reason = reason


class LibraryError(PmkError):
    """A maps-folder operation failed (download, import, convert, delete)."""

    def __init__(self, message: str, *, name: str | None = None, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.name = name


class MapsFolderMissing(LibraryError):
    """The maps folder to read does not exist (a mistyped ``--maps-dir``): never listed as an empty folder.

    Attributes:
        path: the folder that is not there.
    """

    def __init__(self, path: str) -> None:
        super().__init__(
            f"the maps folder {path} does not exist",
            hint="Check --maps-dir; `pmk maps import FILE` creates the folder.",
        )
        self.path = path


class AlreadyExists(LibraryError):
    """A map of that name exists and overwriting was not asked for."""


class DownloadError(LibraryError):
    """A building plan could not be fetched from its URL."""

    def __init__(self, message: str, *, url: str, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.url = url


class DownloadTooLarge(DownloadError):
    """A download is (or announces itself) over the size cap.

    Attributes:
        limit: the cap in bytes; size: the announced length, or the bytes received when cut off.
    """

    def __init__(self, message: str, *, url: str, limit: int, size: int, hint: str = "") -> None:
        super().__init__(message, url=url, hint=hint)
        self.limit = limit
        self.size = size


class AddressRefused(DownloadError):
    """A download (or one of its redirects) would reach a local or private address.

    Attributes:
        host: the host name of the URL or redirect that was refused.
        address: the resolved address that is not public.
        reason: which kind of address it is ("loopback address", "private (LAN) address", ...).
    """

    def __init__(self, *, url: str, host: str, address: str, reason: str) -> None:
        where = f"{host} is a {reason}" if host == address else f"{host} resolves to {address}, a {reason}"
        super().__init__(
            f"download of {url} refused: {where}; downloads reach only public addresses",
            url=url,
            hint="To download from a server on this machine or the lab network, use --allow-local "
            "(pmk maps download, catalogue, get; pmk dashboard).",
        )
        self.host = host
        self.address = address
        self.reason = reason


class ChairLinkError(PmkError):
    """The rosbridge connection to a chair failed or a chair service misbehaved."""

    def __init__(self, message: str, *, host: str | None = None, port: int | None = None, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.host = host
        self.port = port


class ChairTimeout(ChairLinkError):
    """The chair did not answer ``operation`` within ``seconds``."""

    def __init__(
        self,
        message: str,
        *,
        operation: str,
        seconds: float,
        host: str | None = None,
        port: int | None = None,
        hint: str = "",
    ) -> None:
        super().__init__(message, host=host, port=port, hint=hint)
        self.operation = operation
        self.seconds = seconds


class ChairCertificateError(ChairLinkError):
    """A ``wss://`` chair's TLS certificate is not trusted; nothing was sent to the chair.

    Attributes:
        presented: SHA-256 fingerprint of the certificate the chair presented ("AB:CD:..." as
            ``openssl x509 -fingerprint -sha256`` prints it), None when the handshake gave none.
        known_certs: the file that holds the pinned fingerprints (the SSH known_hosts' sibling).
    """

    def __init__(
        self, message: str, *, host: str, port: int, presented: str | None, known_certs: str, hint: str = ""
    ) -> None:
        super().__init__(message, host=host, port=port, hint=hint)
        self.presented = presented
        self.known_certs = known_certs


class UnknownChairCertificate(ChairCertificateError):
    """First contact: no fingerprint is pinned for this chair yet. Only a person who compared
    ``presented`` with the chair's may pin it (:func:`pmk_nb.chair.link.transport.tls.trust_certificate`)."""


class ChairCertificateChanged(ChairCertificateError):
    """The chair presented another certificate than the pinned one (``expected``): refused."""

    def __init__(self, message: str, *, host: str, port: int, presented: str, expected: str, known_certs: str) -> None:
        super().__init__(message, host=host, port=port, presented=presented, known_certs=known_certs)
        self.expected = expected


class ChairCertificateUntrusted(ChairCertificateError):
    """The certificate failed the check against the profile's CA file (``ca_file``); ``reason`` is
    OpenSSL's verify message (e.g. "certificate has expired", "Hostname mismatch")."""

    def __init__(self, message: str, *, host: str, port: int, presented: str | None, ca_file: str, reason: str) -> None:
        super().__init__(message, host=host, port=port, presented=presented, known_certs="")
        self.ca_file = ca_file
        self.reason = reason


class UnsupportedOperation(PmkError):
    """The other side does not offer an operation (e.g. an SFTP server without POSIX rename)."""

    def __init__(self, message: str, *, operation: str, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.operation = operation


class RosNotInstalled(UnsupportedOperation):
    """A chair-side command (`pmk robot ...`) needs ROS and this Python cannot import it.

    Attributes:
        module: the module that is missing (``rclpy``, ``nav_msgs``, ...).
        command: the command that needed it (``map-server``, ``sim-node``, ``goal-watchdog``).
    """

    def __init__(self, message: str, *, module: str, command: str, hint: str = "") -> None:
        super().__init__(message, operation=command, hint=hint)
        self.module = module
        self.command = command


class TransferError(PmkError):
    """Copying a map to the chair over SFTP failed."""

    def __init__(self, message: str, *, host: str | None = None, path: str | None = None, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.host = host
        self.path = path


class UnknownHostKey(TransferError):
    """The chair presented an SSH host key nobody has confirmed yet (strict checking, the dashboard).

    Attributes:
        key_type, fingerprint ("SHA256:..."), key_base64: the key as presented, so the one key the
            user saw and confirmed is the one recorded (:func:`pmk_nb.chair.ssh.trust_host_key`).
        known_hosts: the file it would be recorded in; ``host`` is the known_hosts name.
    """

    def __init__(
        self, message: str, *, host: str, key_type: str, fingerprint: str, key_base64: str, known_hosts: str
    ) -> None:
        super().__init__(message, host=host)
        self.key_type = key_type
        self.fingerprint = fingerprint
        self.key_base64 = key_base64
        self.known_hosts = known_hosts


class DeployError(PmkError):
    """Sending, reloading or confirming a map on the chair failed.

    Attributes:
        step: the deploy step that failed ("upload", "detect", "reload", "confirm"), if known.
        keeps_old_map: True when the chair certainly still runs its previous map, False when it may
            have switched, None when nobody can tell.
    """

    def __init__(
        self, message: str, *, step: str | None = None, keeps_old_map: bool | None = None, hint: str = ""
    ) -> None:
        super().__init__(message, hint=hint)
        self.step = step
        self.keeps_old_map = keeps_old_map


class SettingsError(PmkError):
    """A chair profile holds an invalid value (``field`` names it, when there is one)."""

    def __init__(self, message: str, *, field: str | None = None, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.field = field


class KioskLocked(PmkError):
    """A kiosk page asked for an action of a screen behind the PIN while it is locked.

    Raised by the kernel itself (``AppContext.require_unlocked``), whatever sent the request: a
    button of a screen that was open before the lock, or a message a page script made up.

    Attributes:
        action: what was refused, in the dashboard's words ("Saving settings").
    """

    def __init__(self, message: str, *, action: str, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.action = action


# -- map catalogues (issue 27): every refusal of an install is a type with the facts as fields --------
class CatalogueError(LibraryError):
    """A map catalogue cannot be published or read, or an install from it is refused (nothing installed).

    Attributes:
        url: the catalogue document or asset at fault (a path when publishing).
    """

    def __init__(self, message: str, *, url: str, name: str | None = None, hint: str = "") -> None:
        super().__init__(message, name=name, hint=hint)
        self.url = url


class AssetMismatch(CatalogueError):
    """A downloaded file's size or SHA-256 differs from what the catalogue declares.

    Attributes:
        asset: the asset's key; field: "size" or "checksum"; expected, actual: the two values.
    """

    def __init__(self, *, url: str, asset: str, field: str, expected: str | int, actual: str | int) -> None:
        super().__init__(
            f"{url}: {field} {actual} differs from the catalogue's {expected}; nothing installed",
            url=url,
            hint="The file changed on the server or was tampered with: publish the catalogue again.",
        )
        self.asset = asset
        self.field = field
        self.expected = expected
        self.actual = actual


class AssetOutsideCatalogue(CatalogueError):
    """A link or asset points outside the catalogue's own folder (``..``, an absolute path, another host).

    Attributes:
        href: the link as written; root: the catalogue's folder URL it must stay inside.
    """

    def __init__(self, *, url: str, href: str, root: str) -> None:
        super().__init__(
            f"{url}: link {href!r} leaves the catalogue's folder {root}; nothing installed",
            url=url,
            hint="Only files inside the catalogue's folder are installed (--allow-host for another host).",
        )
        self.href = href
        self.root = root


class RedirectRefused(CatalogueError):
    """The server redirects a catalogue file to another scheme (https -> http) or outside the catalogue.

    Attributes:
        target: where the redirect points.
    """

    def __init__(self, *, url: str, target: str) -> None:
        super().__init__(f"{url}: the server redirects to {target!r}; refused, nothing installed", url=url)
        self.target = target


class AssetTooLarge(CatalogueError):
    """A catalogue file is over the size cap (declared, or when the server sends more).

    Attributes:
        asset: the asset's key; size: bytes declared or received; limit: the cap in bytes.
    """

    def __init__(self, *, url: str, asset: str, size: int, limit: int) -> None:
        super().__init__(
            f"{url}: {size} bytes, more than the limit of {limit} bytes; nothing installed",
            url=url,
            hint="Raise the limit (--max-mb) if you trust this catalogue.",
        )
        self.asset = asset
        self.size = size
        self.limit = limit
