"""Every notebook in notebooks/ runs top to bottom in a fresh venv kernel (nbclient)."""

from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

REPO = Path(__file__).resolve().parents[2]
NOTEBOOKS = REPO / "notebooks"
WIDGET_MIME = "application/vnd.jupyter.widget-view+json"


def run_notebook(
    path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, timeout: int = 180
) -> nbformat.NotebookNode:
    monkeypatch.setenv("PMK_MAPS_DIR", str(tmp_path / "maps"))
    monkeypatch.setenv("PMK_CONFIG_DIR", str(tmp_path / "config"))
    monkeypatch.delenv("MPLBACKEND", raising=False)  # plots must come out as inline images
    monkeypatch.delenv("PMK_CHAIR_PROFILE", raising=False)
    nb = nbformat.read(path, as_version=4)
    client = NotebookClient(
        nb, kernel_name="python3", timeout=timeout, resources={"metadata": {"path": str(NOTEBOOKS)}}
    )
    client.execute()
    return nb


def outputs(nb: nbformat.NotebookNode) -> list[dict]:
    return [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]


def test_kernel_is_this_venv() -> None:
    """nbclient's "python3" kernel must be this venv's interpreter, not a system Python."""
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("import sys; print(sys.executable)")])
    NotebookClient(nb, kernel_name="python3", timeout=60).execute()
    printed = nb.cells[0].outputs[0]["text"].strip()
    assert Path(printed).resolve() == Path(sys.executable).resolve()


def test_notebooks_are_clean_json() -> None:
    """Committed notebooks carry no outputs (they are run by this test, not stored run)."""
    found = sorted(p.name for p in NOTEBOOKS.glob("*.ipynb"))
    expected = {"dashboard.ipynb", "01-indoorgml-to-ros-map.ipynb", "02-chair-data.ipynb", "04-recording-tables.ipynb"}
    assert expected <= set(found)
    for name in found:
        nb = json.loads((NOTEBOOKS / name).read_text())
        assert nb["metadata"]["kernelspec"]["name"] == "python3"
        assert all(not c.get("outputs") for c in nb["cells"] if c["cell_type"] == "code"), name


@pytest.mark.slow
def test_dashboard_notebook_shows_the_app(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    nb = run_notebook(NOTEBOOKS / "dashboard.ipynb", tmp_path, monkeypatch)
    outs = outputs(nb)
    assert not [o for o in outs if o.get("output_type") == "error"]
    assert any(WIDGET_MIME in o.get("data", {}) for o in outs), outs


@pytest.mark.slow
def test_conversion_notebook_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    nb = run_notebook(NOTEBOOKS / "01-indoorgml-to-ros-map.ipynb", tmp_path, monkeypatch)
    outs = outputs(nb)
    images = [o for o in outs if "image/png" in o.get("data", {})]
    assert len(images) >= 3  # the grid plot, the rooms + graph beside the map (issue 29), the preview image
    text = "".join(o.get("text", "") for o in outs)
    assert "round trip OK" in text
    graph = re.search(r"navigation graph: (\d+) nodes, (\d+) edges;", text)
    assert graph and int(graph.group(1)) >= 10 and int(graph.group(2)) >= 10, text


@pytest.mark.slow
def test_chair_data_notebook_records_the_simulator(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PMK_RECORD_SECONDS", "4")  # the notebook's default is 10 s; the flow is the same
    nb = run_notebook(NOTEBOOKS / "02-chair-data.ipynb", tmp_path, monkeypatch)
    outs = outputs(nb)
    text = "".join(o.get("text", "") for o in outs)
    assert "Started a simulated chair" in text
    recorded = [line for line in text.splitlines() if line.startswith("recorded ")]
    assert recorded and int(recorded[0].split()[1]) > 20  # 50 Hz odometry for 4 s
    assert "chair.mcap" in recorded[0] and "0 dropped" in recorded[0]
    read_back = [line for line in text.splitlines() if "odometry messages from" in line]  # the MCAP file read back
    assert read_back and int(read_back[0].split()[0]) == int(recorded[0].split()[1]), read_back
    assert len([o for o in outs if "image/png" in o.get("data", {})]) >= 3  # speed over time, trajectory, scan


@pytest.mark.slow
def test_recording_tables_notebook_records_opens_and_plots(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 40: record the simulated chair, open the file as tables (DataFrames with pandas, rows
    without, saying why), draw the drive."""
    monkeypatch.setenv("PMK_RECORD_SECONDS", "4")
    nb = run_notebook(NOTEBOOKS / "04-recording-tables.ipynb", tmp_path, monkeypatch)
    outs = outputs(nb)
    assert not [o for o in outs if o.get("output_type") == "error"]
    text = "".join(o.get("text", "") for o in outs)
    recorded = re.search(r"recorded (\d+) messages .* (\d+) dropped", text)
    assert recorded and int(recorded.group(1)) > 50 and recorded.group(2) == "0", text
    rows = re.search(r"/odom\s+(\d+) rows,\s+(\d+) columns", text)
    assert rows and int(rows.group(1)) > 20 and int(rows.group(2)) > 10, text  # flattened odometry
    assert "no message on: /cmd_vel" in text or "no message on: none" in text, text
    has_pandas = importlib.util.find_spec("pandas") is not None
    assert ("/odom as a DataFrame" in text) if has_pandas else ("'pandas'" in text and "not installed" in text), text
    odometry = re.search(r"(\d+) odometry rows over ([\d.]+) s", text)
    assert odometry and int(odometry.group(1)) == int(rows.group(1)) and float(odometry.group(2)) > 2.0, text
    assert len([o for o in outs if "image/png" in o.get("data", {})]) >= 1  # the drive figure
