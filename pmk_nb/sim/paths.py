"""The simulated chair's file system: one mapping shared by the map server and the SFTP endpoint.

The chair keeps maps in ``~/ALMA_MAPS`` (the original app's folder). In the simulator that folder
is ``maps_dir`` on the host, and the chair user's home is the virtual ``/home/<user>``. So a map
uploaded over SFTP to ``ALMA_MAPS/x.yaml``, ``~/ALMA_MAPS/x.yaml`` or ``/home/<user>/ALMA_MAPS/x.yaml``
is the same file the map server loads for any of those paths.

Map server only (the sim runs on the host, tests hand it real files): a relative path resolves
against ``maps_dir`` (its working folder), ``~`` is not expanded (real map servers do not), and an
absolute host path outside the virtual maps folder is used as it is, and then refused by the reader
(``read_map(within=maps_dir)``: a chair's map server reads only its maps folder, issue 30).
"""

from __future__ import annotations

import os
import posixpath
from collections.abc import Iterable
from pathlib import Path

MAPS_FOLDER = "ALMA_MAPS"


class ChairFS:
    """Virtual chair paths <-> host paths."""

    def __init__(self, maps_dir: Path, user: str = "pmk") -> None:
        self.maps_dir = Path(maps_dir).resolve()
        self.user = user
        self.home = f"/home/{user}"
        self.maps_virtual = f"{self.home}/{MAPS_FOLDER}"

    def virtual(self, path: str) -> str:
        """Normalised absolute virtual path (``~`` and relative paths start at the home folder)."""
        path = path.strip()
        if path == "~" or path.startswith("~/"):
            path = self.home + path[1:]
        elif not path.startswith("/"):
            path = posixpath.join(self.home, path)
        return posixpath.normpath(path).replace("//", "/")

    def in_maps(self, virtual: str) -> Path | None:
        """Host path for a virtual path inside ``~/ALMA_MAPS``, else None."""
        if virtual == self.maps_virtual:
            return self.maps_dir
        if virtual.startswith(self.maps_virtual + "/"):
            return self.maps_dir / virtual[len(self.maps_virtual) + 1 :]
        return None

    def to_virtual(self, host: Path) -> str | None:
        """Virtual path of a host path inside ``maps_dir``, else None."""
        try:
            rel = Path(host).resolve().relative_to(self.maps_dir)
        except ValueError:
            return None
        return self.maps_virtual if str(rel) == "." else f"{self.maps_virtual}/{rel.as_posix()}"

    def map_server_path(self, path: str) -> Path:
        """Where the map server reads ``path`` (a YAML path from a reload service request).

        Like ROS 1 map_server and Nav2: no ``~`` expansion, and a relative path is read from the
        server's working folder (here ``maps_dir``), so ``~/ALMA_MAPS/x.yaml`` is not found, as on a
        real chair.
        """
        raw = path.strip()
        if raw.startswith("/"):
            found = self.in_maps(posixpath.normpath(raw))
            return found if found is not None else Path(raw)
        return self.maps_dir / raw


def inside_roots(host: Path, roots: Iterable[Path]) -> bool:
    """True if the REAL path of ``host`` (every symlink followed) is one of ``roots`` or below one.

    A path that does not exist yet resolves through its existing parents, so a new file is checked
    by the folder it would land in; a symlink, even a dangling one, is checked by its target.
    ``roots`` must already be real paths (resolved).
    """
    real = Path(os.path.realpath(host))
    return any(real == root or real.is_relative_to(root) for root in roots)


def holds_a_root(host: Path, roots: Iterable[Path]) -> bool:
    """True if the REAL path of ``host`` is one of ``roots`` or a folder above one: what a rename or
    rmdir must never touch (``rename("ALMA_MAPS", "../moved")`` moved the chair's maps folder away)."""
    real = Path(os.path.realpath(host))
    return any(root == real or root.is_relative_to(real) for root in roots)
