"""The Maps screen's witness panel: the map judged against its plan, in words and in a picture."""

from __future__ import annotations

import base64
import io
import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from pmk_nb.access import sidecar_path
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.maps.screen import MapsScreen
from pmk_nb.witness import WITNESS_KEY, VerdictState, witness_map
from tests.helpers import wait_until
from tests.witness.test_witness_cli import SAMPLE, _open_wall

pytestmark = pytest.mark.slow  # each test converts the clinic


def _clinic(screen: MapsScreen, ctx: AppContext) -> Path:
    """The clinic converted in the screen's maps folder (as Convert does), then selected; its YAML."""
    screen.import_bytes("clinic.gml", SAMPLE.read_bytes())
    thread = screen.convert()
    assert thread is not None
    thread.join(120)
    [gm] = ctx.maps.entry("clinic").generated
    return gm.yaml


def _edit_rooms(yaml: Path, witness: object | None) -> None:
    """Hand-edit the rooms file: the verdict replaced, or removed (None: a map converted before the witness)."""
    path = sidecar_path(yaml)
    doc = json.loads(path.read_text(encoding="utf-8"))
    if witness is None:
        del doc[WITNESS_KEY]
    else:
        doc[WITNESS_KEY] = witness
    path.write_text(json.dumps(doc), encoding="utf-8")


def _reselect(screen: MapsScreen) -> None:
    screen.refresh()  # what Refresh does: the rooms file read again


def _picture_png(screen: MapsScreen) -> bytes:
    [item] = screen.witness_panel.images.children
    html = str(item.value)
    assert 'class="pmk-witness-picture"' in html and "alt=" in html
    return base64.b64decode(html.split("base64,")[1].split('"')[0])


def _leak_ring_drawn(png: bytes) -> bool:
    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))
    return bool(np.any(np.all(rgb == (220, 20, 60), axis=-1)))


def test_after_convert_the_map_agrees_without_reloading(screen: MapsScreen, ctx: AppContext) -> None:
    _clinic(screen, ctx)
    panel = screen.witness_panel
    assert panel.widget.layout.display == "flex"
    assert "The map agrees with the plan" in panel.text.value and "pmk-ok" in panel.text.value
    assert [v.state for v in panel.verdicts] == [VerdictState.AGREES]
    assert panel.images.children == ()
    assert panel.widget in screen.widget.children[0].children[0].children[1].children  # beside the access panel


def test_a_painted_leak_is_listed_with_its_rooms_and_place_and_ringed(screen: MapsScreen, ctx: AppContext) -> None:
    yaml = _clinic(screen, ctx)
    _open_wall(yaml)
    report, _grid = witness_map(yaml, chair_width=0.7)  # what `pmk check` says of the files now
    _edit_rooms(yaml, report.to_json())
    _reselect(screen)
    text = screen.witness_panel.text.value
    assert "The map DISAGREES with the plan: 1 finding" in text and "pmk-warn" in text
    assert "<ol class='pmk-witness-list'><li>leak: " in text
    assert "Waiting room" in text and "Exam room 1" in text and " at (10." in text
    wait_until(lambda: screen.witness_panel.images.children, 60, "the witness's picture")
    assert _leak_ring_drawn(_picture_png(screen))


def test_an_unwitnessed_map_offers_the_check_which_finds_the_leak(screen: MapsScreen, ctx: AppContext) -> None:
    yaml = _clinic(screen, ctx)
    _edit_rooms(yaml, None)  # converted before the witness
    _open_wall(yaml)
    _reselect(screen)
    panel = screen.witness_panel
    assert "This map has not been witnessed" in panel.text.value
    assert panel.check_button.layout.display != "none" and panel.check_button.description == "Check against the plan"
    panel.check_button.click()
    wait_until(lambda: "DISAGREES" in panel.text.value, 60, "the check's verdict")
    assert "leak: " in panel.text.value and "Checked" in panel.status.value
    assert _leak_ring_drawn(_picture_png(screen))


def test_the_check_says_when_the_plan_is_gone(screen: MapsScreen, ctx: AppContext) -> None:
    yaml = _clinic(screen, ctx)
    _edit_rooms(yaml, None)
    _reselect(screen)
    (yaml.parent / "clinic.gml").rename(yaml.parent.parent / "elsewhere.gml")
    panel = screen.witness_panel
    panel.check_button.click()
    wait_until(lambda: "pmk-msg-error" in panel.status.value, 60, "the check's failure")
    assert "which is not there" in panel.status.value and "the witness needs the plan" in panel.status.value
    assert "not been witnessed" in panel.text.value  # the verdict did not change
    assert not panel.check_button.disabled


@pytest.mark.parametrize("bad", ["garbage", {"storey": "0", "graph": True, "findings": [{"kind": "flood"}]}])
def test_a_malformed_verdict_says_unreadable(screen: MapsScreen, ctx: AppContext, bad: object) -> None:
    yaml = _clinic(screen, ctx)
    _edit_rooms(yaml, bad)
    _reselect(screen)
    text = screen.witness_panel.text.value
    assert "witness verdict unreadable" in text and "pmk-warn" in text
    assert "Wheelchair access" in screen.access_panel.text.value  # the rest of the screen still shows
    assert screen.witness_panel.images.children == ()
