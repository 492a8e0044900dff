"""``python -m pmk_nb.cli``: the same as the ``pmk`` command."""

from __future__ import annotations

import sys

from pmk_nb.cli import main

sys.exit(main())
