"""The deploy's last step: does the chair publish the map we sent? Never by pulling a big grid when
something smaller can tell.

In order: the PMK map server's MapInfo (the SHA-256 of its cells against ours, computed while the
map travels); else the published metadata (size, resolution, origin) and then the cells, all of them
up to :data:`DATA_CHECK_MAX_CELLS`, sampled rows above. After a lost reload answer the link may be
reconnecting: it is given a moment first.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

from pmk_nb.errors import DeployError, PmkError
from pmk_nb.wire import grid_sha256

if TYPE_CHECKING:
    from pmk_nb.chair.link.streams.messages import MapInfo
    from pmk_nb.rosmap import ImageReader, MapFiles

DATA_CHECK_MAX_CELLS = 1_000_000
SAMPLED_ROWS = 16  # rows compared when a grid is too big to compare whole


class ConfirmLink(Protocol):
    """What the confirmation needs of a chair link: the map's metadata, and a connect once it is known to
    be closed. ``is_connected``, ``map_facts``, ``fetch_map`` and ``ros_version`` are used when the link
    has them (tests' stand-ins may not)."""

    def map_info(self, timeout: float = 5.0, without_grid: bool = False) -> MapInfo: ...
    def connect(self, timeout: float = 5.0) -> None: ...


@dataclass(frozen=True)
class ExpectedMap:
    """Metadata of the map we wrote, as the chair's map server should publish it."""

    width: int
    height: int
    resolution: float
    origin: tuple[float, float]

    def matches(self, info: Any) -> bool:
        ox, oy = float(info.origin[0]), float(info.origin[1])
        tol = max(1e-4, self.resolution * 1e-3)
        return (
            int(info.width) == self.width
            and int(info.height) == self.height
            and math.isclose(float(info.resolution), self.resolution, rel_tol=1e-5)
            and abs(ox - self.origin[0]) <= tol
            and abs(oy - self.origin[1]) <= tol
        )

    def describe(self) -> str:
        return f"{self.width}x{self.height} at {self.resolution:g} m, origin ({self.origin[0]:g}, {self.origin[1]:g})"


def _wait_for_map(link: ConfirmLink, expected: ExpectedMap, deadline: float, timeout: float) -> Any:
    """Poll map_info until it matches ``expected`` or the deadline passes."""
    while True:
        remaining = deadline - time.monotonic()
        try:
            info = link.map_info(timeout=max(0.5, remaining))  # a big /map may take long to cross
        except PmkError:
            info = None
        if info is not None and expected.matches(info):
            return info
        if time.monotonic() >= deadline:
            raise _still_publishes(info, expected, timeout)
        time.sleep(0.2)


def _still_publishes(info: Any, expected: ExpectedMap, timeout: float, cells: bool = False) -> DeployError:
    got = f"{info.width}x{info.height} at {info.resolution:g} m" if info is not None else "no map"
    what = "a map of the same size but different cells" if cells else got
    return DeployError(
        f"the chair still publishes {what} after {timeout:g} s, expected {expected.describe()}; "
        "the reload may not have taken effect (is the map server the one that was reloaded?)",
        step="confirm",
        keeps_old_map=None,
    )


def map_sha256(files: MapFiles) -> str:
    """SHA-256 of our cells as the PMK map server publishes them: read by its reader, hashed as it hashes."""
    from pmk_nb.rosmap import read_map

    return grid_sha256(read_map(files.yaml, reader="nav2_jazzy"))


def _wait_connected(link: ConfirmLink, deadline: float) -> None:
    """After a lost answer the bridge may have closed the link: let it reconnect (or connect it)."""
    if not hasattr(link, "is_connected"):
        return
    until = min(deadline, time.monotonic() + 3.0)
    while not link.is_connected and time.monotonic() < until:
        time.sleep(0.05)
    if not link.is_connected:
        try:
            link.connect(timeout=max(0.5, deadline - time.monotonic()))
        except PmkError:
            pass  # the checks below fail with "no map" and the deploy says so


def _by_map_info(
    link: ConfirmLink,
    expected: ExpectedMap,
    ours_of: Callable[[], str],
    remote_yaml: str,
    deadline: float,
    timeout: float,
) -> tuple[MapInfo, str] | None:
    """Confirm with the PMK map server's MapInfo (no grid moved); None when the chair has none."""
    facts_of = getattr(link, "map_facts", None)
    ours: str | None = None
    facts = None
    while facts_of is not None:
        try:
            facts = facts_of(timeout=max(0.5, min(3.0, deadline - time.monotonic())))
            if facts is None:
                return None
        except PmkError:
            facts = None  # busy or reconnecting: ask again
        if facts is not None and facts.loaded and expected.matches(facts.info):
            if ours is None:
                try:
                    ours = ours_of()
                except PmkError:
                    ours = ""  # our file cannot be read here: the path decides
            if facts.sha256 == ours:
                return facts.info, "SHA-256 of the cells (map_info)"
            if facts.path == remote_yaml:
                return facts.info, "map_info (the file sent; the chair's reader decodes some cells differently)"
        if time.monotonic() >= deadline:
            info = facts.info if facts is not None and facts.loaded else None
            raise _still_publishes(info, expected, timeout, cells=info is not None and expected.matches(info))
        time.sleep(0.1)
    return None


def chair_readers(link: ConfirmLink) -> tuple[ImageReader, ...]:
    """The image readers the chair's map server may be: ROS 1's on a ROS 1 chair, Nav2's (Jazzy, then Humble:
    the link cannot tell which) on a ROS 2 chair, all three when the version is unknown. A scale-mode map
    reads differently under ROS 1's rules and Nav2's (issue 40: a map that loaded was 'different cells')."""
    from pmk_nb.rosmap import READERS

    version = getattr(link, "ros_version", None)
    if version == 1:
        return ("ros1",)
    if version == 2:
        return ("nav2_jazzy", "nav2_humble")
    return READERS


def _cells_match(ours: Any, theirs: Any) -> bool:
    if theirs.data.shape != ours.data.shape:
        return False
    if ours.data.size <= DATA_CHECK_MAX_CELLS:
        return bool((theirs.data == ours.data).all())
    rows = sorted({round(i * (ours.height - 1) / (SAMPLED_ROWS - 1)) for i in range(SAMPLED_ROWS)})
    return bool((theirs.data[rows] == ours.data[rows]).all())


def confirm_map(
    link: ConfirmLink,
    expected: ExpectedMap,
    before: Any,
    files: MapFiles,
    timeout: float,
    remote_yaml: str = "",
    ours_of: Callable[[], str] | None = None,
) -> tuple[Any, str]:
    """MapInfo's SHA-256 when the chair has it; else the metadata, then the cells (all, or sampled rows)."""
    deadline = time.monotonic() + timeout
    _wait_connected(link, deadline)
    by_info = _by_map_info(link, expected, ours_of or (lambda: map_sha256(files)), remote_yaml, deadline, timeout)
    if by_info is not None:
        return by_info
    info = _wait_for_map(link, expected, deadline, timeout)
    if (before is not None and not expected.matches(before)) or not hasattr(link, "fetch_map"):
        return info, "metadata"
    from pmk_nb.rosmap import read_map

    theirs = link.fetch_map(timeout=max(2.0, deadline - time.monotonic()))
    for reader in chair_readers(link):  # our file read as the chair's map server reads it
        ours = read_map(files.yaml, reader=reader)
        if _cells_match(ours, theirs):
            how = "cells" if ours.data.size <= DATA_CHECK_MAX_CELLS else f"metadata and {SAMPLED_ROWS} sampled rows"
            return info, how
    raise _still_publishes(info, expected, timeout, cells=True)


def in_background(fn: Callable[[MapFiles], str], files: MapFiles) -> Callable[[], str]:
    """Start ``fn(files)`` on a daemon thread; the returned function waits for its result (or raises its error)."""
    box: dict[str, Any] = {}
    done = threading.Event()

    def work() -> None:
        try:
            box["value"] = fn(files)
        except Exception as err:  # raised where the result is wanted
            box["error"] = err
        finally:
            done.set()

    threading.Thread(target=work, name="pmk-deploy-sha256", daemon=True).start()

    def result() -> str:
        done.wait()
        if "error" in box:
            raise box["error"]
        return str(box["value"])

    return result
