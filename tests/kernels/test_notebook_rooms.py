"""Notebook 03 runs against the simulator: three rooms visited by name, each one arrived in."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.kernels.test_notebooks import NOTEBOOKS, outputs, run_notebook


@pytest.mark.slow
@pytest.mark.timeout(420)
def test_visit_rooms_notebook_arrives_in_three_rooms(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    nb = run_notebook(NOTEBOOKS / "03-visit-rooms.ipynb", tmp_path, monkeypatch, timeout=300)
    outs = outputs(nb)
    assert not [o for o in outs if o.get("output_type") == "error"], outs
    text = "".join(o.get("text", "") for o in outs)
    assert "You are in: Waiting room" in text
    assert "arrived in 3 of 3 rooms: ['Exam room 2', 'Treatment room', 'Office']" in text, text
    assert "no accessible route to Exam room 1" in text and "Door Waiting room" in text
    assert any("image/png" in o.get("data", {}) for o in outs)  # the routes plotted
    assert any("audio/wav" in str(o.get("data", {}).get("text/html", "")) for o in outs)  # the phrase, audible
