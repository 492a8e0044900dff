"""Safe, streaming XML event source for IndoorGML files.

Building plans arrive from URLs typed by users, so the parser must never expand entities, fetch
DTDs or touch the network/local files (XXE), and must not be made to hang (billion laughs). We
refuse any DOCTYPE that declares entities before lxml sees the document, and parse with
``resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False``.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import BinaryIO

from lxml import etree

from pmk_nb.errors import IndoorGMLError

ProgressFn = Callable[[int, int], None]

PROLOG_LIMIT = 1 << 20  # a DOCTYPE/prolog longer than 1 MiB is not a building plan
_ROOT_START = re.compile(rb"<(?![?!])")
_ENTITY_DECL = re.compile(rb"<!ENTITY", re.IGNORECASE)
_COMMENT = re.compile(rb"<!--.*?-->", re.DOTALL)


class _CountingReader:
    """File wrapper that reports progress as lxml pulls bytes."""

    def __init__(self, fh: BinaryIO, total: int, progress: ProgressFn | None) -> None:
        self._fh = fh
        self._total = total
        self._progress = progress
        self.bytes_read = 0

    def read(self, size: int = -1) -> bytes:
        data = self._fh.read(size)
        self.bytes_read += len(data)
        if self._progress is not None and data:
            self._progress(self.bytes_read, self._total)
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
        raise IndoorGMLError(f"{path}: no root element in the first MiB (prolog too long)")
    prolog = text if m is None else text[: m.start()]
    doctype = prolog.upper().find(b"<!DOCTYPE")
    if doctype >= 0 and (_ENTITY_DECL.search(prolog, doctype) or b"SYSTEM" in prolog[doctype:].upper()):
        raise IndoorGMLError(
            f"{path}: refused: the DOCTYPE declares entities or an external DTD (possible XXE / "
            "entity-expansion attack); IndoorGML files never need one - remove the DOCTYPE"
        )


def iter_events(
    path: str | os.PathLike[str], progress: ProgressFn | None = None
) -> Iterator[tuple[str, etree._Element]]:
    """Yield lxml ``("start"|"end", element)`` events; errors become IndoorGMLError.

    The caller is expected to clear elements it has consumed so memory stays bounded.
    """
    p = Path(path)
    try:
        total = p.stat().st_size
        fh = p.open("rb")
    except OSError as err:
        raise IndoorGMLError(f"{p}: cannot open: {err.strerror or err}") from err
    with fh:
        if total == 0:
            raise IndoorGMLError(f"{p}: the file is empty (expected an IndoorGML document)")
        head = fh.read(PROLOG_LIMIT)
        check_prolog(p, head)
        fh.seek(0)
        reader = _CountingReader(fh, total, progress)
        events = etree.iterparse(
            reader,
            events=("start", "end"),
            resolve_entities=False,
            no_network=True,
            load_dtd=False,
            huge_tree=False,
            remove_comments=True,
            remove_pis=True,
            dtd_validation=False,
        )
        open_tags: list[str] = []
        last_id: list[str | None] = []
        try:
            for event, elem in events:
                if event == "start":
                    open_tags.append(_short(elem))
                    last_id.append(elem.get("{http://www.opengis.net/gml/3.2}id"))
                else:
                    open_tags.pop()
                    last_id.pop()
                yield event, elem
        except etree.XMLSyntaxError as err:
            where = f"line {err.lineno}" if err.lineno else "unknown line"
            inside = ""
            if open_tags:
                ident = next((i for i in reversed(last_id) if i), None)
                inside = f" inside <{open_tags[-1]}>" + (f" (near gml:id={ident!r})" if ident else "")
            kind = "not XML" if not open_tags and reader.bytes_read <= len(head) else "malformed XML"
            msg = err.msg or str(err)
            raise IndoorGMLError(f"{p}: {kind} at {where}{inside}: {msg}") from err
        if progress is not None:
            progress(total, total)


def _short(elem: etree._Element) -> str:
    q = etree.QName(elem)
    prefix = elem.prefix
    return f"{prefix}:{q.localname}" if prefix else q.localname
