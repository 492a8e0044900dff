"""What a chair offers, asked through rosapi: topics by type, services, the map reload service.

ROS 1 rosapi answers ``pkg/Type`` spellings and ROS 2 ``pkg/msg/Type``; callers may use either.

A bridge may run without rosapi (rosbridge-server-rs ``--no-rosapi``, a rosbridge launched without
the rosapi node). Then a ``/rosapi/*`` call fails at once; that is raised as :class:`RosapiMissing`
(plain words, not the bridge's raw text) and remembered for the connection, and the map reload tries
the known reload services by name instead of listing them. A late answer (a busy bridge) is a
:class:`~pmk_nb.errors.ChairTimeout`, never taken for a missing rosapi.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from pmk_nb.chair.link.query import reload
from pmk_nb.chair.link.query.reload import MapReloadError, ReloadService, build_request, check_response
from pmk_nb.chair.link.transport.services import AnswerLost, ServiceFailed
from pmk_nb.errors import ChairLinkError, ChairTimeout
from pmk_nb.wire import normalise_type, type_ros_version, type_spellings

CORE = ("/rosapi/topics", "/rosapi/services")  # every rosapi has these: failing, rosapi is missing
Caller = Callable[[str, str, dict[str, Any], "float | None"], dict[str, Any]]


class RosapiMissing(ChairLinkError):
    """The bridge has no rosapi, so topics and services cannot be listed.

    Attributes:
        service: the rosapi service that failed; ``answer`` what the bridge said.
    """

    def __init__(self, where: str, service: str, answer: str) -> None:
        super().__init__(
            f"the rosbridge server at {where} runs without rosapi ({service} is missing), so PMK Notebook "
            "cannot list the chair's topics and services",
            hint="Type topic names by hand, or start rosapi with the bridge (rosbridge-server-rs without "
            "--no-rosapi; rosbridge_suite: the rosapi node).",
        )
        self.service = service
        self.answer = answer


class Discovery:
    """rosapi queries over a blocking service-call function (the link's ``_call``)."""

    def __init__(self, call: Caller, where: str = "the chair") -> None:
        self._call = call
        self.where = where
        self.rosapi: bool | None = None  # None: not asked yet on this connection

    def forget(self) -> None:
        """A new connection: the bridge may have changed (restarted with rosapi, say)."""
        self.rosapi = None

    def _rosapi(self, name: str, type_name: str, args: dict[str, Any], timeout: float | None) -> dict[str, Any]:
        try:
            answer = self._call(name, type_name, args, timeout)
        except ServiceFailed as err:  # not a timeout (a busy bridge), not "not connected"
            if name not in CORE:
                raise  # an old rosapi may lack this one call
            self.rosapi = False
            raise RosapiMissing(self.where, name, err.answer) from err
        self.rosapi = True
        return answer

    def topics(self, timeout: float | None = None) -> dict[str, str]:
        """{topic: type} from /rosapi/topics (types may be "" on old rosapi versions)."""
        r = self._rosapi("/rosapi/topics", "rosapi/Topics", {}, timeout)
        names, types = list(r.get("topics") or []), list(r.get("types") or [])
        if len(types) != len(names):
            types = [""] * len(names)
        return dict(zip(names, types, strict=True))

    def topics_of_type(self, msg_type: str) -> list[str]:
        """Topics of ``msg_type``; asks /rosapi/topics_for_type with both spellings and merges.

        Falls back to filtering /rosapi/topics when topics_for_type is unavailable.

        Raises:
            RosapiMissing: the bridge has no rosapi.
        """
        found: list[str] = []
        errors: list[str] = []
        for spelling in type_spellings(msg_type):
            try:
                r = self._rosapi("/rosapi/topics_for_type", "rosapi/TopicsForType", {"type": spelling}, None)
            except ChairLinkError as err:  # missing (old rosapi, or none: topics() below tells)
                errors.append(str(err))
                continue
            found += [t for t in r.get("topics") or [] if t not in found]
        if found or len(errors) < len(type_spellings(msg_type)):
            return found
        want = normalise_type(msg_type)
        return [t for t, ty in self.topics().items() if ty and normalise_type(ty) == want]

    def message_details(self, msg_type: str, timeout: float | None = None) -> list[dict[str, Any]]:
        """rosapi's typedefs of ``msg_type`` (the type first, then each type it uses), asked in each
        spelling; [] when the bridge cannot describe it (rosapi 1.x fails the call for an unknown type,
        2.x answers none).

        Raises:
            RosapiMissing: the bridge has no rosapi; ChairLinkError: the call failed otherwise.
        """
        for spelling in type_spellings(msg_type):
            try:
                r = self._rosapi("/rosapi/message_details", "rosapi/MessageDetails", {"type": spelling}, timeout)
            except ServiceFailed:
                continue
            typedefs = [d for d in r.get("typedefs") or [] if isinstance(d, dict)]
            if typedefs:
                return typedefs
        return []

    def services(self) -> list[str]:
        r = self._rosapi("/rosapi/services", "rosapi/Services", {}, None)
        return list(r.get("services") or [])

    def service_type(self, name: str) -> str | None:
        """The service's type via /rosapi/service_type, None when rosapi cannot tell."""
        try:
            r = self._rosapi("/rosapi/service_type", "rosapi/ServiceType", {"service": name}, None)
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

    def reload_plan(self, kind: str | None, service: str | None) -> list[ReloadService]:
        """The reload services to try, in order: the one rosapi finds, else (no rosapi) the known
        names of ``kind`` (or the named ``service``) with their known protocols.

        Raises:
            MapReloadError: rosapi shows no suitable service (nothing was called).
        """
        try:
            return [self.reload_target(kind, service, self.where)]
        except RosapiMissing:
            return reload.known_candidates(kind, service)

    def reload(self, remote_yaml_path: str, kind: str | None, service: str | None, timeout: float) -> ReloadService:
        """Load ``remote_yaml_path`` with the first service of :meth:`reload_plan` that exists.

        A candidate that fails at once (absent from the chair: the bridge says so immediately)
        is skipped; the first one that answers decides. Returns the service that loaded the map.

        Raises:
            MapReloadError: refused (``keeps_old_map=True``), answer lost (None), or none exists.
        """
        plan = self.reload_plan(kind, service)
        tried: list[str] = []
        for target in plan:
            try:
                response = self._call(
                    target.name, target.service_type, build_request(target.kind, remote_yaml_path), timeout
                )
            except ChairTimeout as err:
                raise MapReloadError(
                    f"{err}. The chair may still be loading {remote_yaml_path}.", service=target.name
                ) from err
            except AnswerLost as err:
                raise MapReloadError(f"{err}", service=target.name) from err
            except ServiceFailed as err:  # absent (said at once) or its callback failed: the next one
                tried.append(f"{target.name}: {err}")
                continue
            except ChairLinkError as err:  # not connected: nothing was sent
                raise MapReloadError(f"{err}", service=target.name, keeps_old_map=True) from err
            check_response(target, remote_yaml_path, response)
            return target
        if len(plan) == 1 and self.rosapi is not False:
            raise MapReloadError(tried[0] if tried else "no reload service", service=plan[0].name, keeps_old_map=True)
        names = ", ".join(t.name for t in plan)
        raise MapReloadError(
            f"the rosbridge server at {self.where} runs without rosapi, and no map reload service answered "
            f"(tried {names}; the chair has none of them, or they failed)",
            hint="Start a map server with one of them, or name the service in the chair profile (reload_service).",
            service=plan[0].name if plan else "",
            keeps_old_map=True,
        )
