"""Which map-reload service a chair offers, what to send it and what its answer means.

Three servers exist in the field (see ARCHITECTURE.md): ROS 1 Noetic map_server ``change_map``
(``nav_msgs/LoadMap``), Nav2 ``/map_server/load_map`` (``nav2_msgs/srv/LoadMap``) and the original
PMK modified map server ``MapUpdate`` (``string path`` -> ``bool done``). Pure functions: the link
does the rosapi calls and hands the answers here.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

from pmk_nb.chair.messages import normalise_type
from pmk_nb.errors import ChairLinkError

Flavour = Literal["ros1", "nav2", "mapupdate"]
FLAVOURS: tuple[str, ...] = ("ros1", "nav2", "mapupdate")

# Preferred names, in the order the detection tries them.
PREFERRED: tuple[tuple[str, Flavour], ...] = (
    ("/change_map", "ros1"),
    ("/map_server/load_map", "nav2"),
    ("/map_update", "mapupdate"),
)

SERVICE_TYPES: dict[str, str] = {
    "ros1": "nav_msgs/LoadMap",
    "nav2": "nav2_msgs/srv/LoadMap",
    "mapupdate": "MapUpdate",
}

LOADMAP_RESULTS: dict[int, str] = {
    0: "success",
    1: "no map given (MAP_DOES_NOT_EXIST): check the path sent to the chair",
    2: "the map image is invalid (INVALID_MAP_DATA)",
    # Nav2 also answers 3 when the YAML file does not exist (yaml-cpp cannot open it).
    3: "the map YAML is missing or invalid (INVALID_MAP_METADATA): check the path and the file",
    255: "the map server failed to load the map (UNDEFINED_FAILURE)",
}

KEEPS_OLD_MAP = "The chair keeps its previous map."


class MapReloadError(ChairLinkError):
    """A reload service answered "failed"; ``code`` is its result code (None for MapUpdate/transport)."""

    def __init__(self, message: str, *, code: int | None = None, service: str = "") -> None:
        super().__init__(message)
        self.code = code
        self.service = service


@dataclass(frozen=True)
class ReloadService:
    """A map reload service on the chair and the protocol it speaks."""

    name: str
    flavour: Flavour

    @property
    def service_type(self) -> str:
        return SERVICE_TYPES[self.flavour]


def flavour_from_type(service_type: str | None) -> Flavour | None:
    """Flavour from a rosapi service type (either ROS spelling), None when unknown."""
    if not service_type:
        return None
    t = normalise_type(service_type)
    if t == "nav_msgs/LoadMap":
        return "ros1"
    if t == "nav2_msgs/LoadMap":
        return "nav2"
    if t.split("/")[-1] == "MapUpdate":
        return "mapupdate"
    return None


def flavour_from_name(name: str) -> Flavour | None:
    """Best guess from a service name when rosapi cannot tell the type."""
    base = name.rstrip("/").rsplit("/", 1)[-1]
    if base == "change_map":
        return "ros1"
    if base == "load_map":
        return "nav2"
    if base in ("map_update", "update_map"):
        return "mapupdate"
    return None


def detect(services: list[str], service_type: Callable[[str], str | None]) -> ReloadService | None:
    """Pick the reload service: /change_map, then /map_server/load_map, then /map_update, then any
    service whose type is a known reload type. ``service_type`` asks rosapi (None if it cannot).
    """
    present = set(services)
    for name, default in PREFERRED:
        if name in present:
            return ReloadService(name, flavour_from_type(service_type(name)) or default)
    # Namespaced or renamed servers: check the types of map-looking services only, so a chair
    # with hundreds of services does not cost hundreds of rosapi calls.
    for name in sorted(s for s in services if "map" in s.lower())[:20]:
        flavour = flavour_from_type(service_type(name))
        if flavour is not None:
            return ReloadService(name, flavour)
    for name in services:
        flavour = flavour_from_name(name)
        if flavour is not None:
            return ReloadService(name, flavour)
    return None


def build_request(flavour: Flavour, remote_yaml_path: str) -> dict[str, Any]:
    """LoadMap (both flavours) takes ``map_url`` (a plain path is accepted); MapUpdate takes ``path``."""
    if flavour == "mapupdate":
        return {"path": remote_yaml_path}
    return {"map_url": remote_yaml_path}


def check_response(service: ReloadService, remote_yaml_path: str, response: dict[str, Any]) -> None:
    """Raise :class:`MapReloadError` unless the response says the map was loaded."""
    where = f"{service.name} ({service.flavour})"
    if service.flavour == "mapupdate":
        done = response.get("done")
        if done is True:
            return
        raise MapReloadError(
            f"{where} answered done={done!r} for {remote_yaml_path}: the map was not loaded. {KEEPS_OLD_MAP}",
            service=service.name,
        )
    raw = response.get("result")
    try:
        code = int(raw)
    except (TypeError, ValueError):
        raise MapReloadError(
            f"{where} gave no result code for {remote_yaml_path} (answer: {str(response)[:120]}). {KEEPS_OLD_MAP}",
            service=service.name,
        ) from None
    if code == 0:
        return
    meaning = LOADMAP_RESULTS.get(code, "unknown result code")
    if service.flavour == "ros1" and code == 255:
        meaning = "map_server could not load it (missing file, bad YAML or image?)"
    raise MapReloadError(
        f"{where} failed to load {remote_yaml_path}: code {code}, {meaning}. {KEEPS_OLD_MAP}",
        code=code,
        service=service.name,
    )
