"""What a chair offers, asked through rosapi: topics by type, services, the map reload service.

ROS 1 rosapi answers ``pkg/Type`` spellings and ROS 2 ``pkg/msg/Type``; callers may use either.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from pmk_nb.chair import reload
from pmk_nb.chair.messages import normalise_type, type_ros_version, type_spellings
from pmk_nb.chair.reload import ReloadService
from pmk_nb.errors import ChairLinkError

Caller = Callable[[str, str, dict[str, Any], "float | None"], dict[str, Any]]


class Discovery:
    """rosapi queries over a blocking service-call function (the link's ``_call``)."""

    def __init__(self, call: Caller) -> None:
        self._call = call

    def topics(self, timeout: float | None = None) -> dict[str, str]:
        """{topic: type} from /rosapi/topics (types may be "" on old rosapi versions)."""
        r = self._call("/rosapi/topics", "rosapi/Topics", {}, timeout)
        names, types = list(r.get("topics") or []), list(r.get("types") or [])
        if len(types) != len(names):
            types = [""] * len(names)
        return dict(zip(names, types, strict=True))

    def topics_of_type(self, msg_type: str) -> list[str]:
        """Topics of ``msg_type``; asks /rosapi/topics_for_type with both spellings and merges.

        Falls back to filtering /rosapi/topics when topics_for_type is unavailable.
        """
        found: list[str] = []
        errors: list[str] = []
        for spelling in type_spellings(msg_type):
            try:
                r = self._call("/rosapi/topics_for_type", "rosapi/TopicsForType", {"type": spelling}, None)
            except ChairLinkError as err:
                errors.append(str(err))
                continue
            found += [t for t in r.get("topics") or [] if t not in found]
        if found or len(errors) < len(type_spellings(msg_type)):
            return found
        want = normalise_type(msg_type)
        return [t for t, ty in self.topics().items() if ty and normalise_type(ty) == want]

    def services(self) -> list[str]:
        r = self._call("/rosapi/services", "rosapi/Services", {}, None)
        return list(r.get("services") or [])

    def service_type(self, name: str) -> str | None:
        """The service's type via /rosapi/service_type, None when rosapi cannot tell."""
        try:
            r = self._call("/rosapi/service_type", "rosapi/ServiceType", {"service": name}, None)
        except ChairLinkError:
            return None
        return r.get("type") or None

    def detect_reload_service(self) -> ReloadService | None:
        return reload.detect(self.services(), self.service_type)

    def ros_version(self) -> int | None:
        """1 or 2 from the spelling of the advertised topic types, None if there are none."""
        types = [t for t in self.topics().values() if t]
        if not types:
            return None
        return max(type_ros_version(t) for t in types)

    def reload_target(self, kind: str | None, service: str | None, where: str) -> ReloadService:
        """The service ``reload_map`` calls : see :func:`reload.resolve`."""
        return reload.resolve(
            self.services(), self.service_type, service=service, kind=kind, where=f"the chair at {where}"
        )
