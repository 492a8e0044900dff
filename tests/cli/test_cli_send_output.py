"""`pmk send`'s terminal output, decided by progress steps/fractions and error fields, never by text."""

from __future__ import annotations

import pytest

from pmk_nb.chair import STEP_SPANS
from pmk_nb.cli.send import deploy_failure, print_progress
from pmk_nb.errors import DeployError
from pmk_nb.progress import Progress


def test_upload_prints_one_line_per_quarter(capsys: pytest.CaptureFixture[str]) -> None:
    show = print_progress()
    end = STEP_SPANS["upload"][1]
    show(Progress("upload", 0.0, "connecting to pmk@chair:22"))
    for sent in range(0, 1001, 10):  # a hundred byte counts, worded in any way
        show(Progress("upload", end * sent / 1000, f"chunk {sent}"))
    show(Progress("upload", end, "sent /home/pmk/ALMA_MAPS/m.yaml"))
    show(Progress("detect", 0.70, "connecting to rosbridge"))
    show(Progress("detect", 0.75, "reload service /change_map (ros1)"))
    lines = capsys.readouterr().out.splitlines()
    upload = [line for line in lines if line.startswith("[upload ]")]
    assert upload[0].endswith("connecting to pmk@chair:22")
    assert [line.split()[-1] for line in upload[1:-2]] == ["250", "500", "750"]  # the quarters' first counts
    assert upload[-2].endswith("chunk 1000") and upload[-1].endswith("sent /home/pmk/ALMA_MAPS/m.yaml")
    assert len(upload) == 6
    assert [line for line in lines if line.startswith("[detect ]")] == [
        "[detect ]  70.0%  connecting to rosbridge",
        "[detect ]  75.0%  reload service /change_map (ros1)",
    ]


def test_failure_text_names_the_step_and_what_is_known() -> None:
    refused = DeployError("code 2. The chair keeps its previous map.", step="reload", keeps_old_map=True)
    assert deploy_failure(refused) == "reload: code 2. The chair keeps its previous map."
    lost = DeployError("timed out", step="reload", keeps_old_map=None)
    assert deploy_failure(lost).startswith("reload: timed out Whether the chair switched to the new map is unknown")
    assert deploy_failure(DeployError("no map", step=None)) == "no map"
