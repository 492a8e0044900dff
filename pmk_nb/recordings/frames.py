"""Rows per topic (:class:`TopicRows`, e.g. ``Tables``) -> one ``pandas.DataFrame`` per topic.
pandas is optional: without it, :class:`MissingPackage`.

Columns: ``received`` and ``stamp`` (seconds since the epoch, floats; ``stamp`` NaN where a message has
no header), then the flattened fields in the order of the first message that has them. Cells of a
sequence hold a numpy array or a list (:mod:`.flatten`). Use ``pd.to_datetime(frame["stamp"], unit="s")``
for dates.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from pmk_nb.recordings.errors import MissingPackage

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped,import-not-found,unused-ignore]  # optional


class TopicRows(Protocol):
    """What frames are made of: a recording's rows per topic and its path (named when pandas is missing).
    :class:`~pmk_nb.recordings.read.Tables` is one; defined here so this module needs nothing of the reader."""

    @property
    def path(self) -> Path: ...

    @property
    def rows(self) -> Mapping[str, list[dict[str, Any]]]: ...


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


def to_frames(tables: TopicRows) -> dict[str, pd.DataFrame]:
    """One DataFrame per topic of ``tables`` (a topic without messages: an empty frame with the time columns)."""
    pandas = require_pandas(str(tables.path))
    frames: dict[str, pd.DataFrame] = {}
    for topic, rows in tables.rows.items():
        columns = columns_of(rows) or ["received", "stamp"]
        frames[topic] = pandas.DataFrame.from_records(rows, columns=columns)
    return frames
