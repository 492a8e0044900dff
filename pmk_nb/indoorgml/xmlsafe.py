"""Safe, streaming XML event source for IndoorGML files.

Building plans arrive from URLs typed by users, so the parser must never expand entities, fetch
DTDs or touch the network/local files (XXE), and must not be made to hang (billion laughs).

Two layers, both used by the reader and by :mod:`pmk_nb.indoorgml.sniff` so they always agree:

* the parser itself: :data:`SAFE_PARSER_OPTIONS` (``resolve_entities=False, no_network=True,
  load_dtd=False, huge_tree=False``) through :func:`pull_parser` / :func:`iterparse`;
* one DOCTYPE rule, :func:`doctype_problem`: a document declaring entities or naming an external
  DTD (``SYSTEM`` or ``PUBLIC``) is refused. The reader also applies it to the raw prolog
  (:func:`check_prolog`) before lxml sees a byte.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, BinaryIO, Literal

from lxml import etree

from pmk_nb.errors import IndoorGMLError, NotWellFormed
from pmk_nb.indoorgml.xmlwhere import began_as_xml, open_elements
from pmk_nb.progress import ProgressCallback, emit

if TYPE_CHECKING:
    from _typeshed import SupportsRead

#: The lxml options every parse of a building plan uses (reader and sniff alike).
SAFE_PARSER_OPTIONS: dict[str, Any] = {
    "resolve_entities": False,
    "no_network": True,
    "load_dtd": False,
    "huge_tree": False,
    "remove_comments": True,
    "remove_pis": True,
    "dtd_validation": False,
}
_EVENTS: tuple[Literal["start"], Literal["end"]] = ("start", "end")

PROLOG_LIMIT = 1 << 20  # a DOCTYPE/prolog longer than 1 MiB is not a building plan
GML_ID = "{http://www.opengis.net/gml/3.2}id"
_ROOT_START = re.compile(rb"<(?![?!])")
_ENTITY_DECL = re.compile(rb"<!ENTITY", re.IGNORECASE)
_COMMENT = re.compile(rb"<!--.*?-->", re.DOTALL)


def pull_parser() -> etree.XMLPullParser:
    """A feed parser with :data:`SAFE_PARSER_OPTIONS` yielding ``start``/``end`` events."""
    return etree.XMLPullParser(events=_EVENTS, **SAFE_PARSER_OPTIONS)


def iterparse(source: SupportsRead[bytes]) -> Any:
    """``lxml.etree.iterparse`` over a binary file with :data:`SAFE_PARSER_OPTIONS`."""
    return etree.iterparse(source, events=_EVENTS, **SAFE_PARSER_OPTIONS)


def doctype_problem(docinfo: Any) -> str | None:
    """The one DOCTYPE rule: why a document must be refused (entities, external DTD), or None.

    ``docinfo`` is ``element.getroottree().docinfo`` once the root element has started.
    """
    dtd = docinfo.internalDTD
    if dtd is not None and any(True for _ in dtd.iterentities()):
        return "its DOCTYPE declares XML entities"
    if docinfo.system_url or docinfo.public_id:
        return f"it refers to an external DTD ({docinfo.system_url or docinfo.public_id})"
    return None


class _CountingReader:
    """File wrapper that reports progress as lxml pulls bytes."""

    def __init__(self, fh: BinaryIO, total: int, progress: ProgressCallback | None) -> None:
        self._fh = fh
        self._total = total
        self._progress = progress
        self.bytes_read = 0

    def read(self, size: int = -1) -> bytes:
        data = self._fh.read(size)
        self.bytes_read += len(data)
        if data:
            emit(self._progress, "read", self.bytes_read / max(self._total, 1), f"{self.bytes_read} bytes")
        return data


def _decode_prolog(head: bytes) -> bytes:
    """Return the prolog as UTF-8-ish bytes so the DOCTYPE scan also works for UTF-16 files."""
    for bom, codec in ((b"\xff\xfe", "utf-16-le"), (b"\xfe\xff", "utf-16-be")):
        if head.startswith(bom):
            return head.decode(codec, errors="replace").encode("utf-8")
    if len(head) > 3 and head[1:2] == b"\x00" and head[0:1] == b"<":
        return head.decode("utf-16-le", errors="replace").encode("utf-8")
    return head


def check_prolog(path: Path, head: bytes) -> None:
    """Refuse documents whose DOCTYPE declares entities (XXE, billion laughs).

    Raises:
        IndoorGMLError: naming the file when the prolog declares entities or is absurdly long.
    """
    text = _COMMENT.sub(b"", _decode_prolog(head))
    m = _ROOT_START.search(text)
    if m is None and len(head) >= PROLOG_LIMIT:
        raise IndoorGMLError(f"{path}: no root element in the first MiB (prolog too long)", path=str(path))
    prolog = text if m is None else text[: m.start()]
    doctype = prolog.upper().find(b"<!DOCTYPE")
    if doctype < 0:
        return
    external = any(word in prolog[doctype:].upper() for word in (b"SYSTEM", b"PUBLIC"))
    if _ENTITY_DECL.search(prolog, doctype) or external:
        raise _refused(path, "the DOCTYPE declares entities or an external DTD")


def _refused(path: Path, why: str) -> IndoorGMLError:
    return IndoorGMLError(
        f"{path}: refused: {why} (possible XXE / entity-expansion attack).",
        path=str(path),
        element="DOCTYPE",
        hint="IndoorGML files never need one: remove the DOCTYPE.",
    )


def iter_events(
    path: str | os.PathLike[str], progress: ProgressCallback | None = None
) -> Iterator[tuple[str, etree._Element]]:
    """Yield lxml ``("start"|"end", element)`` events; errors become IndoorGMLError.

    The caller is expected to clear elements it has consumed so memory stays bounded.
    """
    p = Path(path)
    try:
        total = p.stat().st_size
        fh = p.open("rb")
    except OSError as err:
        raise IndoorGMLError(f"{p}: cannot open: {err.strerror or err}", path=str(p)) from err
    with fh:
        if total == 0:
            raise IndoorGMLError(f"{p}: the file is empty (expected an IndoorGML document)", path=str(p))
        head = fh.read(PROLOG_LIMIT)
        check_prolog(p, head)
        fh.seek(0)
        reader = _CountingReader(fh, total, progress)
        events = iterparse(reader)
        depth = 0  # only to find the root's start: where the elements stood at an error is read from the file
        try:
            for event, elem in events:
                if event == "start":
                    if depth == 0 and (why := doctype_problem(elem.getroottree().docinfo)):
                        raise _refused(p, why)
                    depth += 1
                else:
                    depth -= 1
                yield event, elem
        except etree.XMLSyntaxError as err:
            raise not_well_formed(p, head, err) from err
        emit(progress, "read", 1.0, f"{total} bytes")


def not_well_formed(path: Path, head: bytes, err: etree.XMLSyntaxError) -> NotWellFormed:
    """The error for a parse that failed, worded from the file's bytes (see :mod:`.xmlwhere`)."""
    line, column = err.position if err.position and err.position[0] else (err.lineno or None, None)
    began = began_as_xml(head)
    stack = open_elements(path, line, column) if began and line else []
    where = f"line {line}" if line else "unknown line"
    inside = ""
    if stack:
        ident = next((e.gml_id for e in reversed(stack) if e.gml_id), None)
        inside = f" inside <{stack[-1].name}>" + (f" (near gml:id={ident!r})" if ident else "")
    kind = "malformed XML" if began else "not XML"
    return NotWellFormed(
        f"{path}: {kind} at {where}{inside}: {err.msg or err}",
        path=str(path),
        line=line,
        column=column,
        began_as_xml=began,
        open_elements=tuple(e.name for e in stack),
    )
