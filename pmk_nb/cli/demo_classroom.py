"""``pmk demo --classroom`` and ``pmk hub``'s class: the converted sample, the SFTP key, the chair cap.

No simulator starts here: each page's kernel starts its own (:mod:`pmk_nb.classroom.seat`) from the
settings file written here, which the kernels find through ``PMK_CLASSROOM``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from pmk_nb.classroom import CLASSROOM_ENV, SETTINGS_FILE, ChairCap, ClassroomSettings, default_max_chairs
from pmk_nb.cli.demo_setup import convert_sample, make_key_pair

STATE_DIR = "classroom"


@dataclass
class Classroom:
    """What :func:`prepare_classroom` made: the settings (and their file) and the kernels' environment."""

    root: Path
    settings: ClassroomSettings
    settings_file: Path
    env: dict[str, str]

    @property
    def cap(self) -> ChairCap:
        return ChairCap(Path(self.settings.state_dir), self.settings.max_chairs)


def prepare_classroom(root: Path, *, gml: Path | None = None, max_chairs: int | None = None) -> Classroom:
    """Convert the sample, make the key pair and write the class's settings; return the class.

    ``max_chairs``: the cap (None: :func:`~pmk_nb.classroom.cap.default_max_chairs`).

    Raises:
        PmkError: the sample is missing or its conversion fails.
        ValueError: ``max_chairs`` below 1.
    """
    from pmk_nb.ui import AUTOSTART_ENV

    if max_chairs is not None and max_chairs < 1:
        raise ValueError(f"--max-chairs must be at least 1, not {max_chairs}")
    root = root.expanduser().resolve()
    _maps, first = convert_sample(root, gml)
    private_key, public_key = make_key_pair(root / "config")
    state_dir = root / STATE_DIR
    state_dir.mkdir(parents=True, exist_ok=True)
    settings = ClassroomSettings(
        map_yaml=str(first.yaml),
        map_name=first.yaml.stem,
        map_preview=str(first.preview) if first.preview else None,
        public_key=str(public_key),
        private_key=str(private_key),
        max_chairs=int(max_chairs if max_chairs is not None else default_max_chairs()),
        state_dir=str(state_dir),
    )
    settings_file = settings.write(state_dir / SETTINGS_FILE)
    env = dict(os.environ)
    env.update({"PMK_MAPS_DIR": str(root / "maps"), CLASSROOM_ENV: str(settings_file), AUTOSTART_ENV: "1"})
    return Classroom(root, settings, settings_file, env)
