"""Send a map to the chair and make it the live map: upload -> detect reload -> reload -> confirm.

The original app uploaded the files and called the modified map server's ``MapUpdate`` service,
trusting ``done=true``. Here each step reports progress and its own error, the reload service is
detected (ROS 1 ``change_map``, Nav2 ``load_map`` or ``MapUpdate``), and the last step checks that
the chair really publishes a map with the size, resolution and origin of the file we wrote.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import yaml
from PIL import Image

from pmk_nb.chair.transfer import HostKeyInfo, upload
from pmk_nb.errors import DeployError, PmkError

if TYPE_CHECKING:
    from pmk_nb.chair.profiles import ChairProfile
    from pmk_nb.rosmap.files import MapFiles

STEPS = ("upload", "detect", "reload", "confirm")
# Share of the overall progress bar each step covers (upload dominates on real links).
STEP_SPANS = {"upload": (0.0, 0.70), "detect": (0.70, 0.75), "reload": (0.75, 0.90), "confirm": (0.90, 1.0)}
StepProgress = Callable[[str, float, str], None]  # (step, overall fraction 0..1, message)
DATA_CHECK_MAX_CELLS = 1_000_000


class DeployStepError(DeployError):
    """A deploy step failed; ``step`` is one of STEPS, the cause is chained."""

    def __init__(self, step: str, message: str) -> None:
        super().__init__(f"{step}: {message}")
        self.step = step


class Link(Protocol):
    """What deploy needs from ``pmk_nb.chair.link.client.ChairLink``."""

    def detect_reload_service(self) -> Any: ...
    def reload_map(self, remote_yaml_path: str, *args: Any, **kwargs: Any) -> Any: ...
    def map_info(self, timeout: float = ...) -> Any: ...


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


@dataclass
class DeployReport:
    remote_yaml: str
    service: Any  # ReloadService(name, flavour)
    map_info: Any  # MapInfo the chair now publishes
    expected: ExpectedMap
    host_key: HostKeyInfo
    bytes_sent: int
    timings: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    @property
    def elapsed(self) -> float:
        return sum(self.timings.values())


def expected_map(files: MapFiles) -> ExpectedMap:
    """Read what the chair should publish from our YAML and the image header (no full decode)."""
    try:
        doc = yaml.safe_load(Path(files.yaml).read_text(encoding="utf-8"))
        ref = Path(str(doc["image"])).expanduser()
        image = ref if ref.is_absolute() else Path(files.yaml).parent / ref
        with Image.open(image) as img:
            width, height = img.size
        origin = doc.get("origin", [0.0, 0.0, 0.0])
        return ExpectedMap(int(width), int(height), float(doc["resolution"]), (float(origin[0]), float(origin[1])))
    except (OSError, KeyError, TypeError, ValueError, IndexError, yaml.YAMLError) as err:
        raise DeployStepError("upload", f"{files.yaml}: cannot read the map to send ({err})") from err


def _resolve_service(link: Link, profile: ChairProfile) -> Any:
    """The service to call: the profile's (flavour from the profile, rosapi or its name) or detected."""
    from pmk_nb.chair import reload as reload_mod

    if profile.reload_service != "auto":
        name = profile.reload_service if profile.reload_service.startswith("/") else "/" + profile.reload_service
        flavour = profile.reload_flavour if profile.reload_flavour != "auto" else None
        discovery = getattr(link, "discovery", None)
        if flavour is None and discovery is not None:
            if name not in discovery.services():
                raise DeployStepError(
                    "detect", f"the chair has no service {name} (reload_service in the chair profile)"
                )
            flavour = reload_mod.flavour_from_type(discovery.service_type(name))
        flavour = flavour or reload_mod.flavour_from_name(name)
        if flavour is None:
            raise DeployStepError(
                "detect", f"cannot tell the kind of {name}: set reload_flavour (ros1, nav2 or mapupdate)"
            )
        return reload_mod.ReloadService(name, flavour)
    detected = link.detect_reload_service()
    if detected is None:
        raise DeployStepError(
            "detect",
            "the chair offers no map reload service (/change_map, /map_server/load_map or /map_update); "
            "start a map server that has one, or set reload_service in the chair profile. "
            "The chair keeps its previous map.",
        )
    if profile.reload_flavour not in ("auto", detected.flavour):
        raise DeployStepError(
            "detect",
            f"the profile asks for a {profile.reload_flavour} reload but the chair offers {detected.name} "
            f"({detected.flavour}); set reload_flavour to auto or name the service in reload_service",
        )
    return detected


def _confirm(link: Link, expected: ExpectedMap, before: Any, files: MapFiles, timeout: float) -> tuple[Any, str]:
    """Poll map_info until it matches; when the old map had the same metadata, compare the cells."""
    deadline = time.monotonic() + timeout
    info: Any = None
    while True:
        remaining = deadline - time.monotonic()
        try:
            info = link.map_info(timeout=max(0.5, min(3.0, remaining)))
        except PmkError:
            info = None
        if info is not None and expected.matches(info):
            break
        if time.monotonic() >= deadline:
            got = f"{info.width}x{info.height} at {info.resolution:g} m" if info is not None else "no map"
            raise DeployStepError(
                "confirm",
                f"the chair still publishes {got} after {timeout:g} s, expected {expected.describe()}; "
                "the reload may not have taken effect (is the map server the one that was reloaded?)",
            )
        time.sleep(0.2)
    if before is None or not expected.matches(before):
        return info, "metadata"
    if expected.width * expected.height > DATA_CHECK_MAX_CELLS or not hasattr(link, "fetch_map"):
        return info, "metadata (same size as the previous map: content not compared)"
    from pmk_nb.rosmap.files import read_map

    ours = read_map(files.yaml)
    theirs = link.fetch_map(timeout=max(2.0, deadline - time.monotonic()))
    if theirs.data.shape != ours.data.shape or not (theirs.data == ours.data).all():
        raise DeployStepError(
            "confirm", "the chair publishes a map of the same size but different cells: the reload did not take"
        )
    return info, "cells"


def deploy(
    files: MapFiles,
    profile: ChairProfile,
    *,
    password: str | None = None,
    link: Link | None = None,
    progress: StepProgress | None = None,
    timeout: float = 15.0,
    reload_timeout: float = 60.0,
    confirm_timeout: float = 10.0,
) -> DeployReport:
    """Upload ``files`` to the chair of ``profile``, reload its map server and confirm the new map.

    Args:
        link: a ChairLink (connected here if it is not); default the kernel's shared link for the
            profile (``get_link``).
        progress: called as ``(step, overall_fraction, message)``; steps are STEPS in order and the
            fraction never goes back (STEP_SPANS gives each step's share).
        timeout: SSH and rosbridge connect/answer timeout in seconds.
        reload_timeout: how long the map server may take to load (LoadMap replies carry the whole map).
        confirm_timeout: how long to wait for the chair to publish the new map.

    Raises:
        DeployStepError: ``.step`` says which step failed; the original error is chained.
    """
    report_to = progress or (lambda step, fraction, message: None)

    def say(step: str, within: float, message: str) -> None:
        lo, hi = STEP_SPANS[step]
        report_to(step, lo + (hi - lo) * min(max(within, 0.0), 1.0), message)

    timings: dict[str, float] = {}
    expected = expected_map(files)
    start = time.monotonic()
    say("upload", 0.0, f"connecting to {profile.ssh_user}@{profile.host}:{profile.ssh_port}")
    try:
        sent = upload(
            files,
            profile,
            password=password,
            timeout=timeout,
            progress=lambda done, total: say("upload", done / max(total, 1), f"{done // 1024} / {total // 1024} KiB"),
        )
    except PmkError as err:
        raise DeployStepError("upload", str(err)) from err
    timings["upload"] = time.monotonic() - start
    notes = []
    if sent.host_key.newly_trusted:
        notes.append(f"trusted the chair's SSH host key {sent.host_key.fingerprint} (first connection)")
    say("upload", 1.0, f"sent {sent.remote_yaml}")

    start = time.monotonic()
    say("detect", 0.0, f"connecting to rosbridge at {profile.host}:{profile.port}")
    try:
        if link is None:
            link = link_for(profile)
        if not getattr(link, "is_connected", True):
            link.connect(timeout=timeout)  # type: ignore[attr-defined]
        service = _resolve_service(link, profile)
        before = _safe_map_info(link)
    except DeployStepError:
        raise
    except PmkError as err:
        raise DeployStepError(
            "detect", f"{err}. The map was uploaded to {sent.remote_yaml}; the chair keeps its previous map."
        ) from err
    timings["detect"] = time.monotonic() - start
    say("detect", 1.0, f"reload service {service.name} ({service.flavour})")

    start = time.monotonic()
    say("reload", 0.0, f"asking {service.name} to load {sent.remote_yaml}")
    try:
        link.reload_map(sent.remote_yaml, flavour=service.flavour, service=service.name, timeout=reload_timeout)
    except PmkError as err:
        message = str(err)
        if "previous map" not in message:
            message += ". The chair keeps its previous map."
        raise DeployStepError("reload", message) from err
    timings["reload"] = time.monotonic() - start
    say("reload", 1.0, "map server answered: loaded")

    start = time.monotonic()
    say("confirm", 0.0, f"waiting for the chair to publish {expected.describe()}")
    info, how = _confirm(link, expected, before, files, confirm_timeout)
    timings["confirm"] = time.monotonic() - start
    notes.append(f"confirmed by {how}")
    say("confirm", 1.0, f"chair publishes {expected.describe()}")
    return DeployReport(sent.remote_yaml, service, info, expected, sent.host_key, sent.bytes_sent, timings, notes)


def link_for(profile: ChairProfile) -> Any:
    """The kernel's shared ChairLink for this profile (not connected yet)."""
    from pmk_nb.chair.link.registry import get_link

    return get_link(profile.host, profile.port, **profile.link_options())


def close_links() -> None:
    """Close the kernel's links (CLI processes, at exit)."""
    from pmk_nb.chair.link.registry import close_all_links

    close_all_links()


def _safe_map_info(link: Link) -> Any:
    try:
        return link.map_info(timeout=2.0)
    except PmkError:
        return None  # no map yet is fine: the confirm step does not need the old one
