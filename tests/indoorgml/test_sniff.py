"""The IndoorGML check run before a file enters the maps folder."""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.errors import LibraryError
from pmk_nb.indoorgml.sniff import check_indoorgml, is_indoorgml_root
from tests.indoorgml_samples import BROKEN_HTML, ENTITY_BOMB, EXTERNAL_DTD, HTML_PAGE, OTHER_XML, two_rooms
from tests.shared_data import INDOORGML_DATA

SHARED = INDOORGML_DATA
ALMA = (
    b'<?xml version="1.0" encoding="UTF-8"?>\n'
    b'<indoorCore:MultiLayeredGraph xmlns:indoorCore="http://www.opengis.net/indoorgml/1.0/core" '
    b'xmlns:indoorNavi="http://www.opengis.net/indoorgml/1.0/navigation" xmlns:gml="http://www.opengis.net/gml/3.2">'
    b"<indoorCore:spaceLayers/></indoorCore:MultiLayeredGraph>\n"
)


def write(tmp_path: Path, data: bytes, name: str = "m.gml") -> Path:
    path = tmp_path / name
    path.write_bytes(data)
    return path


def test_every_shared_sample_is_indoorgml() -> None:
    files = sorted(SHARED.glob("*.gml"))
    assert len(files) >= 8, f"expected the shared IndoorGML samples in {SHARED}"
    for path in files:
        assert check_indoorgml(path).root == "IndoorFeatures", path


@pytest.mark.parametrize(
    ("data", "root"),
    [
        (ALMA, "MultiLayeredGraph"),
        (two_rooms(), "IndoorFeatures"),
        (b'<x:Doc xmlns:x="http://www.opengis.net/indoorgml/2.0/core"/>', "Doc"),
        (b'<PrimalSpaceFeatures xmlns="urn:unknown"/>', "PrimalSpaceFeatures"),
        ('<?xml version="1.0" encoding="UTF-16"?><IndoorFeatures/>'.encode("utf-16"), "IndoorFeatures"),
    ],
)
def test_accepted(tmp_path: Path, data: bytes, root: str) -> None:
    assert check_indoorgml(write(tmp_path, data)).root == root


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (b"   \n", "is empty"),
        (HTML_PAGE, "web page"),
        (BROKEN_HTML, "not a well-formed XML"),
        (ENTITY_BOMB, "declares XML entities"),
        (EXTERNAL_DTD, "external DTD"),
        (OTHER_XML, "not IndoorGML"),
        (b"\x89PNG\r\n\x1a\n" + b"\0" * 50, "not a well-formed XML"),
        (two_rooms() + b"<trailing/>", "not a well-formed XML"),
    ],
)
def test_refused(tmp_path: Path, data: bytes, message: str) -> None:
    path = write(tmp_path, data)
    with pytest.raises(LibraryError, match=message) as info:
        check_indoorgml(path, what="the file at http://x/y")
    assert str(info.value).startswith("the file at http://x/y")


def test_root_rules() -> None:
    assert is_indoorgml_root("Anything", "http://www.opengis.net/indoorgml/1.0.3/core")
    assert not is_indoorgml_root("html", "http://www.w3.org/1999/xhtml")
    assert not is_indoorgml_root("CityModel", "http://www.opengis.net/citygml/2.0")


@pytest.mark.slow
def test_large_file_is_checked_in_chunks(tmp_path: Path) -> None:
    # ~4 MiB, several read chunks: elements split across chunk borders must not confuse the check
    cell = b'<cellSpaceMember><CellSpace gml:id="C"><gml:name>room</gml:name></CellSpace></cellSpaceMember>'
    data = (
        b'<IndoorFeatures xmlns="http://www.opengis.net/indoorgml/1.0/core" '
        b'xmlns:gml="http://www.opengis.net/gml/3.2">' + cell * 45_000 + b"</IndoorFeatures>"
    )
    assert check_indoorgml(write(tmp_path, data)).root == "IndoorFeatures"
