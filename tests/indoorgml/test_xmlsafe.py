"""The XML parser's own defences, hit directly (no regex pre-check in front), and the one DOCTYPE rule
that the reader and the sniff share.

Each hostile document is fed to :func:`pmk_nb.indoorgml.xmlsafe.pull_parser` and to
:func:`~pmk_nb.indoorgml.xmlsafe.iterparse` themselves, so these tests fail if a safety flag of
``SAFE_PARSER_OPTIONS`` is flipped (``resolve_entities`` expands the entities and reads the local
file; ``load_dtd`` loads the external DTD).
"""

from __future__ import annotations

import io
import threading
import time
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest
from lxml import etree

from pmk_nb.errors import IndoorGMLError, LibraryError
from pmk_nb.indoorgml import read_building
from pmk_nb.indoorgml.sniff import check_indoorgml
from pmk_nb.indoorgml.xmlsafe import doctype_problem, iterparse, pull_parser

SECRET = "TOP-SECRET-9f3a"
NS = 'xmlns="http://www.opengis.net/indoorgml/1.0/core"'


def laughs(levels: int) -> bytes:
    """Billion laughs: each entity is ten of the previous one (10**levels "lol"s when expanded)."""
    decls = ['<!ENTITY lol0 "lol">'] + [f'<!ENTITY lol{i} "{f"&lol{i - 1};" * 10}">' for i in range(1, levels + 1)]
    return f"<!DOCTYPE r [{''.join(decls)}]><r>&lol{levels};</r>".encode()


def parse_pull(data: bytes) -> etree._Element:
    parser = pull_parser()
    parser.feed(data)
    parser.close()
    ends = [elem for event, elem in parser.read_events() if event == "end"]
    return ends[-1]


def parse_iter(data: bytes) -> etree._Element:
    root = None
    for event, elem in iterparse(io.BytesIO(data)):
        if event == "end":
            root = elem
    assert root is not None
    return root


PARSERS = [parse_pull, parse_iter]


@pytest.fixture
def secret_file(tmp_path: Path) -> Path:
    path = tmp_path / "secret.txt"
    path.write_text(SECRET)
    return path


@pytest.fixture
def external_dtd(tmp_path: Path) -> Path:
    path = tmp_path / "ext.dtd"
    path.write_text(f'<!ENTITY e "{SECRET}">\n<!ELEMENT r ANY>\n')
    return path


@pytest.mark.parametrize("parse", PARSERS)
@pytest.mark.realtime  # a time bound is the point: an expanded entity bomb takes minutes
def test_internal_entities_are_not_expanded(parse) -> None:
    small = parse(laughs(2))  # 100 "lol"s if expanded
    assert "lol" not in etree.tostring(small, encoding="unicode").replace("&lol2;", "")
    started = time.monotonic()
    try:
        bomb = parse(laughs(9))  # 10**9 "lol"s if expanded: never built
    except etree.XMLSyntaxError as err:  # refused outright (libxml2's amplification limit) is fine too
        assert "amplification" in str(err.msg).lower() or "entity" in str(err.msg).lower()
    else:
        assert etree.tostring(bomb, encoding="unicode") == "<r>&lol9;</r>"
    assert time.monotonic() - started < 2.0


@pytest.mark.parametrize("parse", PARSERS)
def test_external_system_entity_does_not_read_the_local_file(parse, secret_file: Path) -> None:
    doc = f'<!DOCTYPE r [<!ENTITY x SYSTEM "{secret_file.as_uri()}">]><r>&x;</r>'.encode()
    root = parse(doc)
    assert SECRET not in etree.tostring(root, encoding="unicode")
    assert etree.tostring(root, encoding="unicode") == "<r>&x;</r>"


@pytest.mark.parametrize("parse", PARSERS)
def test_public_external_dtd_is_not_loaded(parse, external_dtd: Path) -> None:
    doc = f'<!DOCTYPE r PUBLIC "-//PMK//Test//EN" "{external_dtd.as_uri()}"><r>&e;</r>'.encode()
    root = parse(doc)
    info = root.getroottree().docinfo
    assert info.externalDTD is None  # the DTD file was never read
    assert SECRET not in etree.tostring(root, encoding="unicode")


class _Recorder(BaseHTTPRequestHandler):
    requests: list[str]

    def log_message(self, format: str, *args: object) -> None:
        pass

    def do_GET(self) -> None:
        self.requests.append(self.path)
        body = f'<!ENTITY e "{SECRET}">'.encode() if self.path.endswith(".dtd") else SECRET.encode()
        self.send_response(200)
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)


@pytest.fixture
def recorder() -> Iterator[tuple[str, list[str]]]:
    requests: list[str] = []
    handler = type("H", (_Recorder,), {"requests": requests})
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}", requests
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(5)


@pytest.mark.parametrize("parse", PARSERS)
@pytest.mark.realtime  # a real HTTP server that must hear nothing
def test_network_references_are_never_fetched(parse, recorder: tuple[str, list[str]]) -> None:
    base, requests = recorder
    docs = [
        f'<r xmlns:xi="http://www.w3.org/2001/XInclude"><xi:include href="{base}/inc.xml" parse="text"/></r>',
        f'<!DOCTYPE r [<!ENTITY x SYSTEM "{base}/entity.txt">]><r>&x;</r>',
        f'<!DOCTYPE r PUBLIC "-//PMK//Test//EN" "{base}/ext.dtd"><r>&e;</r>',
    ]
    for doc in docs:
        root = parse(doc.encode())
        assert SECRET not in etree.tostring(root, encoding="unicode")
    time.sleep(0.1)
    assert requests == []


# ---------------------------------------------------------------- one DOCTYPE rule for reader and sniff
def hostile_documents(secret: Path, dtd: Path) -> dict[str, bytes]:
    body = f"<IndoorFeatures {NS}/>"
    return {
        "entities": laughs(3).replace(b"<r>&lol3;</r>", body.encode()).replace(b"DOCTYPE r", b"DOCTYPE IndoorFeatures"),
        "system entity": f'<!DOCTYPE IndoorFeatures [<!ENTITY x SYSTEM "{secret.as_uri()}">]>{body}'.encode(),
        "public dtd": f'<!DOCTYPE IndoorFeatures PUBLIC "-//PMK//Test//EN" "{dtd.as_uri()}">{body}'.encode(),
        "system dtd": f'<!DOCTYPE IndoorFeatures SYSTEM "{dtd.as_uri()}">{body}'.encode(),
    }


def test_the_rule_names_every_hostile_doctype(secret_file: Path, external_dtd: Path) -> None:
    for name, doc in hostile_documents(secret_file, external_dtd).items():
        root = parse_pull(doc)
        assert doctype_problem(root.getroottree().docinfo), name
    plain = parse_pull(f"<!DOCTYPE IndoorFeatures><IndoorFeatures {NS}/>".encode())
    assert doctype_problem(plain.getroottree().docinfo) is None


def test_reader_and_sniff_refuse_the_same_files(tmp_path: Path, secret_file: Path, external_dtd: Path) -> None:
    for name, doc in hostile_documents(secret_file, external_dtd).items():
        path = tmp_path / f"{name.replace(' ', '_')}.gml"
        path.write_bytes(doc)
        with pytest.raises(LibraryError, match="refused for safety"):
            check_indoorgml(path)
        with pytest.raises(IndoorGMLError, match="refused") as info:
            read_building(path)
        assert info.value.path == str(path) and info.value.element == "DOCTYPE"


def test_safe_options_pin_every_flag() -> None:
    """``no_network`` cannot be observed above: this libxml2 has no HTTP client, so a network DTD or
    entity fails to load whatever the flag says. Pin it (and the others) here instead."""
    from pmk_nb.indoorgml.xmlsafe import SAFE_PARSER_OPTIONS

    assert SAFE_PARSER_OPTIONS["no_network"] is True
    assert (SAFE_PARSER_OPTIONS["resolve_entities"], SAFE_PARSER_OPTIONS["load_dtd"]) == (False, False)
    assert SAFE_PARSER_OPTIONS["huge_tree"] is False
