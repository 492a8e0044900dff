"""Where the project's shared real-world test data lives (``shared/`` beside the checkout).

CI clones the repo with ``shared/`` next to it; ``PMK_SHARED_DIR`` points elsewhere. A missing
folder is an error, not a reason to skip: these tests are the proof that real files work.
"""

from __future__ import annotations

import os
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def shared_dir() -> Path:
    candidates = [Path(p) for p in [os.environ.get("PMK_SHARED_DIR", "")] if p]
    candidates += [REPO.parent / "shared", Path("/work/shared")]
    for path in candidates:
        if (path / "data").is_dir():
            return path
    tried = ", ".join(str(p) for p in candidates)
    raise RuntimeError(f"shared test data not found (tried {tried}); set PMK_SHARED_DIR to the shared/ folder")


SHARED = shared_dir()
INDOORGML_DATA = Path(os.environ.get("PMK_INDOORGML_DATA", SHARED / "data" / "indoorgml"))
MAP_SERVER_DATA = SHARED / "data" / "map_server"
