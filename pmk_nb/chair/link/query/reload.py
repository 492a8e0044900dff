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

from pmk_nb.errors import ChairLinkError
from pmk_nb.wire import (
    INVALID_MAP_DATA,
    INVALID_MAP_METADATA,
    LOAD_SUCCESS,
    MAP_DOES_NOT_EXIST,
    UNDEFINED_FAILURE,
    normalise_type,
)

# Which reload protocol a service speaks (the simulator's ROS 1/ROS 2 choice is its RosVersion).
ReloadKind = Literal["ros1", "nav2", "mapupdate"]
RELOAD_KINDS: tuple[str, ...] = ("ros1", "nav2", "mapupdate")

# Preferred names, in the order the detection tries them.
PREFERRED: tuple[tuple[str, ReloadKind], ...] = (
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
    LOAD_SUCCESS: "success",
    MAP_DOES_NOT_EXIST: "no map given (MAP_DOES_NOT_EXIST): check the path sent to the chair",
    INVALID_MAP_DATA: "the map image is invalid (INVALID_MAP_DATA)",
    # Nav2 also answers 3 when the YAML file does not exist (yaml-cpp cannot open it).
    INVALID_MAP_METADATA: "the map YAML is missing or invalid (INVALID_MAP_METADATA): check the path and the file",
    UNDEFINED_FAILURE: "the map server failed to load the map (UNDEFINED_FAILURE)",
}

KEEPS_OLD_MAP = "The chair keeps its previous map."


class MapReloadError(ChairLinkError):
    """A map reload did not happen.

    Attributes:
        code: the LoadMap result code (None for MapUpdate, a missing service or a transport failure).
        service: the service that was (or would have been) called.
        keeps_old_map: True when the chair certainly still runs its previous map (the service
            answered "failed", or none was called); None when the answer was lost. The text says so.
    """

    def __init__(
        self,
        message: str,
        *,
        code: int | None = None,
        service: str = "",
        keeps_old_map: bool | None = None,
        hint: str = "",
    ) -> None:
        super().__init__(message, hint=hint)
        self.code = code
        self.service = service
        self.keeps_old_map = keeps_old_map

    @property
    def detail(self) -> str:
        """The text without the keeps-its-map sentence (callers that state it themselves use this)."""
        return super().__str__()

    def __str__(self) -> str:
        return f"{self.detail} {KEEPS_OLD_MAP}" if self.keeps_old_map else self.detail


@dataclass(frozen=True)
class ReloadService:
    """A map reload service on the chair and the protocol it speaks."""

    name: str
    kind: ReloadKind

    @property
    def service_type(self) -> str:
        return SERVICE_TYPES[self.kind]


def kind_from_type(service_type: str | None) -> ReloadKind | None:
    """ReloadKind from a rosapi service type (either ROS spelling), None when unknown."""
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


def kind_from_name(name: str) -> ReloadKind | None:
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
            return ReloadService(name, kind_from_type(service_type(name)) or default)
    # Namespaced or renamed servers: check the types of map-looking services only, so a chair
    # with hundreds of services does not cost hundreds of rosapi calls.
    for name in sorted(s for s in services if "map" in s.lower())[:20]:
        kind = kind_from_type(service_type(name))
        if kind is not None:
            return ReloadService(name, kind)
    for name in services:
        kind = kind_from_name(name)
        if kind is not None:
            return ReloadService(name, kind)
    return None


def resolve(
    services: list[str],
    service_type: Callable[[str], str | None],
    *,
    service: str | None = None,
    kind: str | None = None,
    where: str = "the chair",
) -> ReloadService:
    """The reload service to call: the one named (its kind given, from rosapi or from its name), else
    the detected one, which must be of ``kind`` when a kind is asked for. The one resolver used by
    both ``ChairLink.reload_map`` and ``deploy``.

    Raises:
        MapReloadError: (``keeps_old_map=True``: nothing was called) naming what is missing.
    """
    if kind is not None and kind not in RELOAD_KINDS:
        raise MapReloadError(
            f"unknown reload kind {kind!r}; use {', '.join(RELOAD_KINDS)}", service=service or "", keeps_old_map=True
        )
    if service is not None:
        name = service if service.startswith("/") else "/" + service
        if name not in services:
            raise MapReloadError(
                f"{where} has no service {name} (check reload_service in the chair profile)",
                service=name,
                keeps_old_map=True,
            )
        found_kind = kind or kind_from_type(service_type(name)) or kind_from_name(name)
        if found_kind is None:
            raise MapReloadError(
                f"cannot tell which reload protocol {name} speaks: set the reload kind ({', '.join(RELOAD_KINDS)})",
                service=name,
                keeps_old_map=True,
            )
        return ReloadService(name, found_kind)  # type: ignore[arg-type]
    if kind is not None:
        wanted = [name for name, preferred in PREFERRED if preferred == kind and name in services]
        if wanted:
            return ReloadService(wanted[0], kind)  # type: ignore[arg-type]
    detected = detect(services, service_type)
    if detected is None:
        raise MapReloadError(
            f"{where} offers no map reload service (looked for /change_map, /map_server/load_map, "
            "/map_update and MapUpdate types)",
            hint="Start a map server that has one, or set reload_service in the chair profile.",
            keeps_old_map=True,
        )
    if kind is not None and detected.kind != kind:
        usual = next(name for name, preferred in PREFERRED if preferred == kind)
        raise MapReloadError(
            f"{where} offers no {kind} reload service such as {usual}; it offers {detected.name} ({detected.kind})",
            hint="Set the reload kind to auto, or name the service in reload_service.",
            service=detected.name,
            keeps_old_map=True,
        )
    return detected


def known_candidates(kind: str | None, service: str | None) -> list[ReloadService]:
    """The reload services to try by name when the bridge cannot list services (no rosapi):
    the named ``service`` (its protocol from ``kind`` or its name), else the known names of
    ``kind``, else all of :data:`PREFERRED` in order.

    Raises:
        MapReloadError: an unknown kind, or a named service whose protocol cannot be told.
    """
    if kind is not None and kind not in RELOAD_KINDS:
        raise MapReloadError(f"unknown reload kind {kind!r}; use {', '.join(RELOAD_KINDS)}", keeps_old_map=True)
    if service is not None:
        name = service if service.startswith("/") else "/" + service
        found = kind or kind_from_name(name)
        if found is None:
            raise MapReloadError(
                f"cannot tell which reload protocol {name} speaks without rosapi: set the reload kind "
                f"({', '.join(RELOAD_KINDS)})",
                service=name,
                keeps_old_map=True,
            )
        return [ReloadService(name, found)]  # type: ignore[arg-type]
    return [ReloadService(name, k) for name, k in PREFERRED if kind is None or k == kind]


def check_remote_path(remote_yaml_path: str) -> None:
    """Refuse a path a map server cannot read before anything is sent.

    ROS 1 map_server and Nav2 do not expand ``~`` and read relative paths from their own working
    folder: Noetic answers 255, Nav2 "map does not exist", and the user learns nothing from either.
    """
    if not remote_yaml_path.startswith("/"):
        raise MapReloadError(
            f"{remote_yaml_path!r} is not an absolute path on the chair: map servers do not expand '~' "
            "and read relative paths from their own working folder",
            keeps_old_map=True,
            hint="Give the full path, e.g. /home/<ssh user>/ALMA_MAPS/<map>.yaml (deploy() finds it over SFTP).",
        )


def build_request(kind: ReloadKind, remote_yaml_path: str) -> dict[str, Any]:
    """LoadMap (both kinds) takes ``map_url`` (a plain path is accepted); MapUpdate takes ``path``."""
    if kind == "mapupdate":
        return {"path": remote_yaml_path}
    return {"map_url": remote_yaml_path}


def check_response(service: ReloadService, remote_yaml_path: str, response: dict[str, Any]) -> None:
    """Raise :class:`MapReloadError` unless the response says the map was loaded."""
    where = f"{service.name} ({service.kind})"
    if service.kind == "mapupdate":
        done = response.get("done")
        if done is True:
            return
        raise MapReloadError(
            f"{where} answered done={done!r} for {remote_yaml_path}: the map was not loaded.",
            service=service.name,
            keeps_old_map=True,
        )
    raw: Any = response.get("result")
    try:
        code = int(raw)
    except (TypeError, ValueError):
        raise MapReloadError(
            f"{where} gave no result code for {remote_yaml_path} (answer: {str(response)[:120]}): "
            "cannot tell whether it loaded the map.",
            service=service.name,
        ) from None
    if code == 0:
        return
    meaning = LOADMAP_RESULTS.get(code, "unknown result code")
    if service.kind == "ros1" and code == UNDEFINED_FAILURE:
        meaning = "map_server could not load it (missing file, bad YAML or image?)"
    raise MapReloadError(
        f"{where} failed to load {remote_yaml_path}: code {code}, {meaning}.",
        code=code,
        service=service.name,
        keeps_old_map=True,
    )
