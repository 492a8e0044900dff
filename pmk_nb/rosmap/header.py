"""An image's size read from its header without decoding: PGM/PBM/PPM, PNG, BMP.

Pillow refuses to even open an image over its decompression-bomb limit, and a large map of ours (a
1 km plan at 0.05 m) is one: listing it must still say its size. The Netpbm header is parsed by its
grammar (issue 38: a comment ended by CR read as 1x1 here while Pillow decoded 4000x4000): the magic
number, then width, height and (PGM/PPM) maxval as decimal tokens separated by whitespace (space,
TAB, CR, LF, VT, FF); a comment runs from ``#`` through the next CR or LF, may stand anywhere before
the last token and is dropped whole (so it may even split a token, as the spec and Pillow say); one
whitespace byte ends the header. A header that breaks the grammar is a :class:`MalformedImageHeader`.
"""

from __future__ import annotations

from pathlib import Path

from pmk_nb.errors import MalformedImageHeader

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
NETPBM_WHITESPACE = b" \t\r\n\x0b\x0c"
#: magic -> header tokens after it (PBM has no maxval)
NETPBM_TOKENS = {b"P1": 2, b"P4": 2, b"P2": 3, b"P5": 3, b"P3": 3, b"P6": 3}
MAX_TOKEN_DIGITS = 10  # Pillow refuses longer tokens
MAX_HEADER_BYTES = 65536  # comments included; map_saver writes about 60
MAX_MAXVAL = 65535


def header_size(path: Path) -> tuple[int, int] | None:
    """(width, height) from a Netpbm, PNG or BMP header, else None (another format: ask Pillow).

    Raises:
        MalformedImageHeader: a Netpbm header that breaks the grammar (naming the file and why).
        OSError: the file cannot be read.
    """
    with open(path, "rb") as fh:
        head = fh.read(MAX_HEADER_BYTES)
    if head.startswith(PNG_SIGNATURE) and head[12:16] == b"IHDR":
        return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")
    if head[:2] == b"BM" and len(head) >= 26:
        if int.from_bytes(head[14:18], "little") == 12:  # OS/2 BITMAPCOREHEADER: 16-bit sides
            return int.from_bytes(head[18:20], "little"), int.from_bytes(head[20:22], "little")
        width = int.from_bytes(head[18:22], "little", signed=True)
        height = int.from_bytes(head[22:26], "little", signed=True)  # negative: rows stored top-down
        return abs(width), abs(height)
    count = NETPBM_TOKENS.get(head[:2])
    if count is None:
        return None
    values = netpbm_tokens(head, count, path)
    return values[0], values[1]


def gray_pgm_layout(path: Path) -> tuple[int, int, int] | None:
    """(width, height, offset of the first pixel byte) of a binary PGM of one byte a sample (maxval 255)
    whose header has no comment, else None: the one layout whose pixels are the file's bytes as they
    stand, and whose header every reader reads alike.

    Raises:
        MalformedImageHeader: a Netpbm header that breaks the grammar. OSError: the file cannot be read.
    """
    with open(path, "rb") as fh:
        head = fh.read(MAX_HEADER_BYTES)
    if head[:2] != b"P5":
        return None
    values, end = _netpbm_header(head, 3, path)
    return (values[0], values[1], end) if values[2] == 255 and b"#" not in head[:end] else None


def netpbm_tokens(head: bytes, count: int, path: Path) -> list[int]:
    """The ``count`` decimal tokens after a Netpbm magic number, by the grammar (see the module)."""
    return _netpbm_header(head, count, path)[0]


def _netpbm_header(head: bytes, count: int, path: Path) -> tuple[list[int], int]:
    """:func:`netpbm_tokens` and the offset just past the whitespace byte that ends the header."""

    def bad(reason: str) -> MalformedImageHeader:
        return MalformedImageHeader(
            f"{path}: malformed {head[:2].decode()} header: {reason}", path=str(path), reason=reason
        )

    if len(head) < 3 or head[2:3] not in NETPBM_WHITESPACE:
        raise bad("no whitespace after the magic number")
    tokens: list[bytes] = []
    token = b""
    pos = 2
    while len(tokens) < count:
        if pos >= len(head):
            raise bad(f"it ends after {len(tokens)} of its {count} numbers" + _cut(head))
        byte = head[pos : pos + 1]
        pos += 1
        if byte == b"#":
            pos = _comment_end(head, pos)
            if pos < 0:
                raise bad("a comment runs past the end of the header" + _cut(head))
        elif byte in NETPBM_WHITESPACE:
            if token:
                tokens.append(token)
                token = b""
        elif byte.isdigit():
            token += byte
            if len(token) > MAX_TOKEN_DIGITS:
                raise bad(f"a number longer than {MAX_TOKEN_DIGITS} digits")
        else:
            raise bad(f"byte {byte!r} at offset {pos - 1} where a decimal number belongs")
    values = [int(t) for t in tokens]
    if 0 in values[:2]:
        raise bad(f"a side of 0 pixels ({values[0]}x{values[1]})")
    if count == 3 and not 0 < values[2] <= MAX_MAXVAL:
        raise bad(f"maxval {values[2]} outside 1..{MAX_MAXVAL}")
    return values, pos


def _comment_end(head: bytes, pos: int) -> int:
    """Offset just past the CR or LF that ends the comment starting before ``pos``; -1 if none."""
    ends = [i for i in (head.find(b"\r", pos), head.find(b"\n", pos)) if i >= 0]
    return min(ends) + 1 if ends else -1


def _cut(head: bytes) -> str:
    return f" (within its first {MAX_HEADER_BYTES} bytes)" if len(head) >= MAX_HEADER_BYTES else ""
