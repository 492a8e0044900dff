"""Where an XML syntax error sits: did the document begin as XML, and which elements were open.

Both answers are read from the file's own bytes, never from the events the parser delivered before it
failed: how many events a parser hands out before it raises depends on how it batches its input
(lxml 6 / libxml2 2.14 parse a whole read buffer before delivering any event, so a document that is
XML for 228 lines and then has a mismatched tag had delivered none). The scan runs only once a parse
has failed, so it may be simple: tags, comments, CDATA, processing instructions and declarations.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

#: a name's first character: anything an XML name may start with that is ASCII-safe to match
_NAME = rb"[^\s<>/!?=&\"'0-9.\-][^\s<>/!?=&\"']*"
_MISC = rb"(?:\s+|<\?.*?\?>|<!--.*?-->|<!DOCTYPE(?:[^\[>]|\[.*?\])*>)"
_BEGINS = re.compile(rb"\A(?:\xef\xbb\xbf)?" + _MISC + rb"*<" + _NAME + rb"(?:[\s/>]|\Z)", re.DOTALL | re.IGNORECASE)
_TOKEN = re.compile(
    rb"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>|<![^>]*>"
    rb"|<(?P<close>/?)(?P<name>" + _NAME + rb")(?P<attrs>(?:[^>\"']|\"[^\"]*\"|'[^']*')*?)(?P<empty>/?)>",
    re.DOTALL,
)
_GML_ID = re.compile(rb"\bgml:id\s*=\s*(?:\"([^\"]*)\"|'([^']*)')")
_UTF16 = ("utf-16-le", "utf-16-be")


@dataclass(frozen=True)
class OpenElement:
    """An element open at the error: its name as written (``prefix:local``) and its gml:id, if any."""

    name: str
    gml_id: str | None


def _as_utf8(head: bytes) -> bytes:
    """UTF-16 documents (with or without a BOM) as UTF-8, so one set of byte patterns reads both."""
    for bom, codec in ((b"\xff\xfe", _UTF16[0]), (b"\xfe\xff", _UTF16[1])):
        if head.startswith(bom):
            return head[2:].decode(codec, errors="replace").encode("utf-8")
    if len(head) > 3 and head[0:1] == b"<" and head[1:2] == b"\x00":
        return head.decode(_UTF16[0], errors="replace").encode("utf-8")
    if len(head) > 3 and head[0:1] == b"\x00" and head[1:2] == b"<":
        return head.decode(_UTF16[1], errors="replace").encode("utf-8")
    return head


def began_as_xml(head: bytes) -> bool:
    """True when the document's first bytes are an XML prolog followed by a root start tag.

    ``head`` is the start of the file (the reader keeps the first MiB); a prolog longer than that is
    refused before parsing anyway.
    """
    return _BEGINS.match(_as_utf8(head)) is not None


def open_elements(path: Path, line: int, column: int | None) -> list[OpenElement]:
    """The elements open just before the error at ``line`` (1-based) and ``column``, outermost first.

    An end tag that does not close the innermost open element is where a mismatch error sits: the scan
    stops there, leaving the element the parser expected to close as the innermost one.
    """
    text = _as_utf8(_through_line(path, line))
    limit = len(text)
    if column is not None and column > 0:
        limit = text.rfind(b"\n", 0, max(len(text) - 1, 0)) + 1 + column
    stack: list[OpenElement] = []
    for m in _TOKEN.finditer(text, 0, len(text)):
        if m.end() > limit:
            break
        name = m.group("name")
        if name is None or m.group("empty"):
            continue
        if m.group("close"):
            if not stack or stack[-1].name != name.decode("utf-8", errors="replace"):
                break
            stack.pop()
            continue
        ident = _GML_ID.search(m.group("attrs"))
        gml_id = None if ident is None else bytes(ident.group(1) or ident.group(2) or b"").decode("utf-8", "replace")
        stack.append(OpenElement(name.decode("utf-8", errors="replace"), gml_id))
    return stack


def _through_line(path: Path, line: int) -> bytes:
    """The file's bytes up to the end of ``line`` (1-based)."""
    lines: list[bytes] = []
    with path.open("rb") as fh:
        for _ in range(max(line, 1)):
            chunk = fh.readline()
            if not chunk:
                break
            lines.append(chunk)
    return b"".join(lines)
