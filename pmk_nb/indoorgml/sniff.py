"""Cheap, safe check that a file is an IndoorGML document before it enters the maps folder.

The original app saved whatever the URL returned; here a download or import is refused unless it is
well-formed XML whose root is an IndoorGML element, so an HTML error page or a truncated transfer
never replaces a good map. The check streams the file (constant memory), never resolves entities,
never touches the network and refuses what the reader refuses: a DOCTYPE declaring entities or naming
an external DTD (one parser factory and one rule, both from :mod:`pmk_nb.indoorgml.xmlsafe`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING

from lxml import etree

from pmk_nb.errors import LibraryError
from pmk_nb.indoorgml.xmlsafe import doctype_problem, pull_parser

if TYPE_CHECKING:
    from pathlib import Path

# Root elements an IndoorGML document may start with (the ALMA servers wrote MultiLayeredGraph).
INDOORGML_ROOTS = frozenset({"IndoorFeatures", "MultiLayeredGraph", "PrimalSpaceFeatures"})
# http://www.opengis.net/indoorgml/1.0/core, .../1.0.3/core, .../2.0/core, .../2.0 ...
_CORE_NS = re.compile(r"^https?://(www\.)?opengis\.net/indoorgml/\d+(\.\d+)*(/core)?/?$", re.IGNORECASE)
_CHUNK = 1 << 20


@dataclass(frozen=True)
class SniffResult:
    """What the check learnt: the root element's local name and namespace URI."""

    root: str
    namespace: str


def is_indoorgml_root(local_name: str, namespace: str) -> bool:
    """True when a root element with this name / namespace is an IndoorGML document."""
    return local_name in INDOORGML_ROOTS or bool(_CORE_NS.match(namespace))


#: what to check when a file is not XML, by where it came from
NOT_XML_HINTS = {
    "url": "Check the URL (a web page or a truncated transfer gives this error).",
    "file": "Choose the building's IndoorGML file (.gml or .xml); a file saved from a web page or cut short "
    "gives this error.",
}


def check_indoorgml(path: Path, *, what: str | None = None, source: str = "file") -> SniffResult:
    """Check that ``path`` is a well-formed IndoorGML XML document.

    Args:
        path: the file to check.
        what: how to name the file in messages (e.g. the URL it came from); defaults to the path.
        source: ``"file"`` or ``"url"``: where it came from, for the advice when it is not XML.

    Returns:
        The root element's local name and namespace.

    Raises:
        LibraryError: empty file, not XML (with the parser's line and message), a DTD declaring
            entities, or XML whose root is not an IndoorGML element (e.g. an HTML page).
    """
    label = what or str(path)
    parser = pull_parser()
    root: SniffResult | None = None
    seen_any = False
    try:
        with open(path, "rb") as fh:
            while chunk := fh.read(_CHUNK):
                seen_any = seen_any or bool(chunk.strip())
                parser.feed(chunk)
                root = _drain(parser, root, label)
            if not seen_any:
                raise LibraryError(f"{label} is empty, not an IndoorGML file")
            parser.close()
            root = _drain(parser, root, label)
    except etree.XMLSyntaxError as err:
        line = f" at line {err.lineno}" if err.lineno else ""
        raise LibraryError(
            f"{label} is not a well-formed XML file{line} ({err.msg}); an IndoorGML map must be XML.",
            hint=NOT_XML_HINTS.get(source, NOT_XML_HINTS["file"]),
        ) from err
    except OSError as err:
        raise LibraryError(f"cannot read {label}: {err.strerror or err}") from err
    if root is None:  # pragma: no cover - lxml raises on a document without a root element
        raise LibraryError(f"{label} has no root element, not an IndoorGML file")
    return root


def _drain(parser: etree.XMLPullParser, root: SniffResult | None, label: str) -> SniffResult | None:
    """Consume pending events: judge the root on its start tag, free finished elements."""
    for event, elem in parser.read_events():
        if event == "start":
            if root is None:
                root = _judge_root(elem, label)
            continue
        # constant memory: drop what has been parsed already
        elem.clear(keep_tail=False)
        parent = elem.getparent()
        if parent is not None:
            while elem.getprevious() is not None:
                del parent[0]
    return root


def _judge_root(elem: etree._Element, label: str) -> SniffResult:
    qname = etree.QName(elem)
    namespace = qname.namespace or ""
    if not is_indoorgml_root(qname.localname, namespace):
        shown = f"{{{namespace}}}{qname.localname}" if namespace else qname.localname
        hint = " (this looks like a web page, not a map)" if qname.localname.lower() == "html" else ""
        raise LibraryError(
            f"{label} is XML but not IndoorGML: its root element is <{shown}>{hint}; expected "
            "IndoorFeatures, MultiLayeredGraph or PrimalSpaceFeatures in an IndoorGML namespace"
        )
    # entities are never expanded here, but the reader refuses such files: they must not enter the folder
    why = doctype_problem(elem.getroottree().docinfo)
    if why:
        raise LibraryError(f"{label} is refused for safety: {why}; IndoorGML files need none")
    return SniffResult(root=qname.localname, namespace=namespace)
