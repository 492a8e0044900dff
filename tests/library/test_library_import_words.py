"""Import errors speak of the user's file, never of a temporary copy, and never suggest a URL."""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.errors import LibraryError
from pmk_nb.indoorgml import check_indoorgml
from pmk_nb.library.folder import MapsFolder


def _refusal(folder: MapsFolder, path: Path, **kw: object) -> LibraryError:
    with pytest.raises(LibraryError) as caught:
        folder.import_file(path, **kw)  # type: ignore[arg-type]
    return caught.value


def test_a_local_file_that_is_not_xml_names_the_file_and_never_says_url(tmp_path: Path) -> None:
    upload = tmp_path / "pmk-upload-x1" / "plan.gml"  # what the Maps screen makes of an upload
    upload.parent.mkdir()
    upload.write_text("<IndoorFeatures><oops></IndoorFeatures>")
    err = _refusal(MapsFolder(tmp_path / "maps"), upload, name="plan", label="ward plan.gml")
    said = f"{err} {err.hint}"
    assert "ward plan.gml" in said and "not a well-formed XML file at line 1" in said
    assert "pmk-upload" not in said and str(tmp_path) not in said
    assert "URL" not in said and ".gml" in err.hint


def test_other_import_refusals_name_the_label_too(tmp_path: Path) -> None:
    folder = MapsFolder(tmp_path / "maps")
    html = tmp_path / "tmpabc" / "saved.gml"
    html.parent.mkdir()
    html.write_text("<html><body>404</body></html>")
    err = _refusal(folder, html, name="saved", label="saved.gml")
    assert str(err).startswith("saved.gml is XML but not IndoorGML") and "tmpabc" not in str(err)
    assert "web page" in str(err)
    missing = _refusal(folder, tmp_path / "tmpabc" / "gone.gml", label="gone.gml")
    assert str(missing) == "cannot import gone.gml: no such file"
    folder_err = _refusal(folder, tmp_path, label="my plans")
    assert "my plans" in str(folder_err) and "a folder" in str(folder_err) and "no such file" not in str(folder_err)


def test_without_a_label_the_path_is_named(tmp_path: Path) -> None:
    plan = tmp_path / "plan.gml"
    plan.write_text("not xml at all <")
    err = _refusal(MapsFolder(tmp_path / "maps"), plan)
    assert str(err).startswith(f"{plan} is not a well-formed XML file")


def test_the_not_xml_advice_depends_on_where_the_file_came_from(tmp_path: Path) -> None:
    page = tmp_path / "body"
    page.write_text("<html><p>unclosed</html>")
    with pytest.raises(LibraryError) as from_url:
        check_indoorgml(page, what="the file at http://127.0.0.1/plan.gml", source="url")
    with pytest.raises(LibraryError) as from_file:
        check_indoorgml(page, what="plan.gml")
    assert "Check the URL" in from_url.value.hint
    assert "URL" not in from_file.value.hint and "IndoorGML file" in from_file.value.hint
