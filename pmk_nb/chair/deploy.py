"""Send a map to the chair and make it the live map: upload -> detect reload -> reload -> confirm.

The original app uploaded the files and called the modified map server's ``MapUpdate`` service,
trusting ``done=true``. Here each step reports progress and its own error, the reload service is
detected (ROS 1 ``change_map``, Nav2 ``load_map`` or ``MapUpdate``; without rosapi the known names
are tried in turn), and the last step checks that the chair really publishes the map we wrote.

Confirming never pulls a big grid when something smaller can tell (see :mod:`.confirm`). A lost
reload answer (timeout, or the bridge closing the link because the answer did not fit its send
queue) is followed by that same check before anything is said.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from PIL import Image

from pmk_nb.chair.confirm import ConfirmLink, ExpectedMap, confirm_map, in_background, map_sha256
from pmk_nb.chair.link.query import reload
from pmk_nb.chair.link.registry import close_all_links, get_link
from pmk_nb.chair.transfer import HostKeyInfo, UploadResult, image_beside, upload
from pmk_nb.errors import DeployError, PmkError
from pmk_nb.progress import ProgressCallback, emit, sub_range

if TYPE_CHECKING:
    from pmk_nb.chair.link import ChairLink
    from pmk_nb.chair.link.query.discovery import Discovery
    from pmk_nb.chair.link.query.reload import ReloadKind, ReloadService
    from pmk_nb.chair.link.streams.messages import MapInfo
    from pmk_nb.chair.profiles import ChairProfile
    from pmk_nb.rosmap import MapFiles

STEPS = ("upload", "detect", "reload", "confirm")
# Share of the overall progress bar each step covers (upload dominates on real links).
STEP_SPANS = {"upload": (0.0, 0.70), "detect": (0.70, 0.75), "reload": (0.75, 0.90), "confirm": (0.90, 1.0)}


class Link(ConfirmLink, Protocol):
    """What deploy needs from ``pmk_nb.chair.link.client.ChairLink``.

    ``discovery`` answers ``services()`` and ``service_type(name)`` (rosapi); ``fetch_map``,
    ``is_connected`` and ``connect`` are used when the link has them.
    """

    discovery: Discovery

    def reload_map(
        self,
        remote_yaml_path: str,
        kind: ReloadKind | str | None = None,
        service: str | None = None,
        timeout: float = 30.0,
    ) -> ReloadService: ...


@dataclass
class DeployReport:
    remote_yaml: str
    service: Any  # ReloadService(name, kind)
    map_info: Any  # MapInfo the chair now publishes
    expected: ExpectedMap
    host_key: HostKeyInfo
    bytes_sent: int
    timings: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    @property
    def elapsed(self) -> float:
        return sum(self.timings.values())


def _cause_text(err: BaseException) -> str:
    """What went wrong, without a keeps-its-map sentence (the DeployError states that from its field)."""
    if isinstance(err, reload.MapReloadError):
        return err.detail
    if isinstance(err, PmkError):
        return str(err)
    return f"{type(err).__name__}: {err}"


def step_failed(step: str, cause: BaseException | str, *, keeps_old_map: bool | None, then: str = "") -> DeployError:
    """The DeployError of ``step``: the cause, what already happened (``then``), whether the old map stays."""
    text = cause if isinstance(cause, str) else _cause_text(cause)
    parts = [text, then, reload.KEEPS_OLD_MAP if keeps_old_map else ""]
    return DeployError(" ".join(p for p in parts if p), step=step, keeps_old_map=keeps_old_map)


def expected_map(files: MapFiles) -> ExpectedMap:
    """Read what the chair should publish from our YAML and the image header (no full decode).

    The image is the one ``upload`` will send (beside the YAML), so a YAML that names another file
    fails here, before anything is sent.
    """
    try:
        doc, image = image_beside(Path(files.yaml))
        with Image.open(image) as img:
            width, height = img.size
    except PmkError as err:
        raise step_failed("upload", err, keeps_old_map=True) from err
    except (OSError, ValueError) as err:  # Pillow: unreadable image
        raise step_failed("upload", f"{files.yaml}: cannot read its image ({err})", keeps_old_map=True) from err
    return ExpectedMap(int(width), int(height), doc.resolution, (doc.origin[0], doc.origin[1]))


class _Steps:
    """One deploy run: progress per step (mapped onto STEP_SPANS) and each step's duration."""

    def __init__(self, progress: ProgressCallback | None) -> None:
        self.progress = progress
        self.timings: dict[str, float] = {}

    def say(self, step: str, within: float, message: str) -> None:
        lo, hi = STEP_SPANS[step]
        emit(self.progress, step, lo + (hi - lo) * min(max(within, 0.0), 1.0), message)

    def within(self, step: str) -> ProgressCallback | None:
        """A callback for a sub-operation of ``step`` reporting 0..1."""
        return sub_range(self.progress, *STEP_SPANS[step])

    @contextmanager
    def timed(self, step: str) -> Iterator[None]:
        start = time.monotonic()
        yield
        self.timings[step] = time.monotonic() - start


def upload_step(
    run: _Steps, files: MapFiles, profile: ChairProfile, password: str | None, timeout: float
) -> UploadResult:
    """Copy the YAML and image into the chair's maps folder; nothing is reloaded yet."""
    with run.timed("upload"):
        run.say("upload", 0.0, f"connecting to {profile.ssh_user}@{profile.host}:{profile.ssh_port}")
        try:
            sent = upload(files, profile, password=password, timeout=timeout, progress=run.within("upload"))
        except PmkError as err:
            raise step_failed("upload", err, keeps_old_map=True) from err
    run.say("upload", 1.0, f"sent {sent.remote_yaml}")
    return sent


def detect_step(run: _Steps, link: Link | None, profile: ChairProfile, sent: UploadResult, timeout: float) -> Any:
    """Connect to rosbridge and pick the reload service (the profile's, else the detected one).

    Returns ``(link, service, map_info before the reload or None)``; ``service`` is None when the
    bridge has no rosapi (the reload then tries the known names); the map is read only when cheap.
    """
    with run.timed("detect"):
        run.say("detect", 0.0, f"connecting to rosbridge at {profile.host}:{profile.port}")
        try:
            if link is None:
                link = link_for(profile)
            if not getattr(link, "is_connected", True):
                link.connect(timeout=timeout)
            plan = _reload_plan(link, profile)
        except PmkError as err:
            raise step_failed(
                "detect", err, keeps_old_map=True, then=f"The map was uploaded to {sent.remote_yaml}."
            ) from err
    before = _map_before(link)
    if len(plan) == 1:
        run.say("detect", 1.0, f"reload service {plan[0].name} ({plan[0].kind})")
        return link, plan[0], before
    names = ", ".join(s.name for s in plan)
    run.say("detect", 1.0, f"the bridge has no rosapi: will try the known reload services in turn ({names})")
    return link, None, before


def _map_before(link: Link) -> MapInfo | None:
    """The current map's metadata when it is cheap to read (MapInfo, /map_metadata), else None: a big
    /map is never pulled here (it cost every later send seconds)."""
    try:
        return link.map_info(timeout=2.0, without_grid=True)
    except TypeError:  # a link without the option (tests' stand-ins)
        return None
    except PmkError:
        return None


def _reload_plan(link: Link, profile: ChairProfile) -> list[ReloadService]:
    service = None if profile.reload_service == "auto" else profile.reload_service
    kind = None if profile.reload_kind == "auto" else profile.reload_kind
    if hasattr(link.discovery, "reload_plan"):
        return list(link.discovery.reload_plan(kind, service))
    discovery = link.discovery
    where = f"the chair at {profile.host}:{profile.port}"
    return [reload.resolve(discovery.services(), discovery.service_type, service=service, kind=kind, where=where)]


def reload_step(run: _Steps, link: Link, service: Any, remote_yaml: str, timeout: float) -> tuple[Any, PmkError | None]:
    """Ask the map server to load the uploaded YAML; returns ``(service that loaded it, lost answer)``.

    A refusal means the chair keeps its old map (raised). A lost answer (timeout, link closed by
    the bridge) is returned, not raised: the confirm step looks at the map before anything is said.
    """
    with run.timed("reload"):
        what = f"{service.name}" if service is not None else "the known reload services"
        run.say("reload", 0.0, f"asking {what} to load {remote_yaml}")
        try:
            kind, name = (service.kind, service.name) if service is not None else (None, None)
            used = link.reload_map(remote_yaml, kind=kind, service=name, timeout=timeout)
        except reload.MapReloadError as err:
            if err.keeps_old_map is not None:
                raise step_failed("reload", err, keeps_old_map=err.keeps_old_map) from err
            run.say("reload", 1.0, "the map server's answer was lost: checking the chair's map")
            return service or reload.ReloadService(err.service, reload.kind_from_name(err.service) or "nav2"), err
        except PmkError as err:
            run.say("reload", 1.0, "the map server's answer was lost: checking the chair's map")
            return service, err
    run.say("reload", 1.0, "map server answered: loaded")
    return (used if isinstance(used, reload.ReloadService) else service), None


def confirm_step(
    run: _Steps,
    link: Link,
    expected: ExpectedMap,
    before: Any,
    files: MapFiles,
    timeout: float,
    remote_yaml: str = "",
    ours_of: Callable[[], str] | None = None,
) -> tuple[Any, str]:
    """Check the chair publishes the map we sent. Returns ``(map_info, how it was confirmed)``.

    ``ours_of`` gives our cells' SHA-256 (deploy computes it while the map travels).
    """
    with run.timed("confirm"):
        run.say("confirm", 0.0, f"waiting for the chair to publish {expected.describe()}")
        info, how = confirm_map(link, expected, before, files, timeout, remote_yaml, ours_of)
    run.say("confirm", 1.0, f"chair publishes {expected.describe()}")
    return info, how


def deploy(
    files: MapFiles,
    profile: ChairProfile,
    *,
    password: str | None = None,
    link: Link | None = None,
    progress: ProgressCallback | None = None,
    timeout: float = 15.0,
    reload_timeout: float = 60.0,
    confirm_timeout: float = 10.0,
) -> DeployReport:
    """Upload ``files`` to the chair of ``profile``, reload its map server and confirm the new map.

    Args:
        link: a ChairLink (connected here if it is not); default the kernel's shared link for the
            profile (``get_link``).
        progress: gets a :class:`~pmk_nb.progress.Progress` per event; ``step`` is one of STEPS in
            order and ``fraction`` (of the whole deploy, STEP_SPANS gives each step's share) never
            goes back. During the upload the fraction follows the bytes sent.
        timeout: SSH and rosbridge connect/answer timeout in seconds.
        reload_timeout: how long the map server may take to load (LoadMap replies carry the whole map).
        confirm_timeout: how long to wait for the chair to publish the new map.

    Raises:
        DeployError: ``step`` says which step failed, ``keeps_old_map`` whether the chair surely
            still runs its previous map; the original error is chained.
    """
    run = _Steps(progress)
    expected = expected_map(files)
    ours = in_background(map_sha256, files)  # ready by the confirm step: the map travels meanwhile
    sent = upload_step(run, files, profile, password, timeout)
    notes = []
    if sent.host_key.newly_trusted:
        notes.append(f"trusted the chair's SSH host key {sent.host_key.fingerprint} (first connection)")
    link, service, before = detect_step(run, link, profile, sent, timeout)
    service, lost = reload_step(run, link, service, sent.remote_yaml, reload_timeout)
    try:
        info, how = confirm_step(run, link, expected, before, files, confirm_timeout, sent.remote_yaml, ours)
    except DeployError as err:
        if lost is None:
            raise
        raise step_failed("reload", lost, keeps_old_map=None, then=f"Checked afterwards: {err}") from lost
    if lost is not None:
        notes.append(f"the map server's answer was lost ({_cause_text(lost)}); the chair's map was checked instead")
    notes.append(f"confirmed by {how}")
    return DeployReport(sent.remote_yaml, service, info, expected, sent.host_key, sent.bytes_sent, run.timings, notes)


def link_for(profile: ChairProfile) -> ChairLink:
    """The kernel's shared ChairLink for this profile (not connected yet)."""
    link = get_link(profile.host, profile.port, **profile.link_options())
    link.goal_policy = profile.goal_policy()
    return link


def close_links() -> None:
    """Close the kernel's links (CLI processes, at exit)."""
    close_all_links()
