"""Tables -> one ``pandas.DataFrame`` per topic. pandas is optional: without it, :class:`MissingPackage`.

Columns: ``received`` and ``stamp`` (seconds since the epoch, floats; ``stamp`` NaN where a message has
no header), then the flattened fields in the order of the first message that has them. Cells of a
sequence hold a numpy array or a list (:mod:`.flatten`). Use ``pd.to_datetime(frame["stamp"], unit="s")``
for dates.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from pmk_nb.recordings.errors import MissingPackage

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped,import-not-found,unused-ignore]  # optional

    from pmk_nb.recordings.read import Tables


def require_pandas(path: str) -> Any:
    """The pandas module.

    Raises:
        MissingPackage: pandas is not installed (``package == "pandas"``).
    """
    try:
        return importlib.import_module("pandas")
    except ImportError:
        raise MissingPackage(path=path, package="pandas", purpose="as DataFrames") from None


def columns_of(rows: list[dict[str, Any]]) -> list[str]:
    """Every column of ``rows``, in first-seen order (``received``, ``stamp`` first)."""
    seen: dict[str, None] = {}
    for item in rows:
        seen |= dict.fromkeys(item)
    return list(seen)


def to_frames(tables: Tables) -> dict[str, pd.DataFrame]:
    """One DataFrame per topic of ``tables`` (a topic without messages: an empty frame with the time columns)."""
    pandas = require_pandas(str(tables.path))
    frames: dict[str, pd.DataFrame] = {}
    for topic, rows in tables.rows.items():
        columns = columns_of(rows) or ["received", "stamp"]
        frames[topic] = pandas.DataFrame.from_records(rows, columns=columns)
    return frames
