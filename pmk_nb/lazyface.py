"""One lazy package face: a name loads only the module that defines it.

The package faces (issue 25) name what other packages use. Imported eagerly, `from pmk_nb.chair import X`
would pull paramiko and roslibpy, and `from pmk_nb.sim import Chair` asyncssh, which the ROS 2 sim
node's environment does not have. Each face keeps its literal ``__all__`` (the layout test reads it)
and its ``TYPE_CHECKING`` imports (what mypy follows).
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Collection, Mapping
from typing import Any


def lazy_face(
    package: str, where: Mapping[str, str], names: Collection[str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``__getattr__`` and ``__dir__`` for ``package``'s face: ``where`` maps a name to its module."""
    namespace = sys.modules[package].__dict__

    def face_getattr(name: str) -> Any:
        if name not in where:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{where[name]}"), name)
        namespace[name] = value  # once is enough
        return value

    def face_dir() -> list[str]:
        return sorted({*namespace, *names})

    return face_getattr, face_dir
