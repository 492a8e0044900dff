"""A real ROS 2 Jazzy stack from the package registry's wheels, for machines with no ROS install.

Used by the real-stack test tier, `make ros2` and `make bench`: a venv of its own (outside the
checkout: ``$PMK_ROS_CACHE`` or ``~/.cache/pmk-ros``) with the Jazzy runtime wheels, the rosbridge
server (``rosbridge-server-rs``) and the interfaces that have no wheel (``ros/interfaces``), built
with cmake against the wheels. Stamps make a second run instant: one for the venv (the lock, `requirements/ros2.txt`)
and one per interface package (its files), so changing one package rebuilds only that package.

The fix-ups the wheels need, found by trying (see the real-ROS issue): the wheels' exported
``.cmake`` files name the manylinux build's Python include dirs; the server binary has no run bit;
``librmw_implementation.so`` must resolve to the FastRTPS one; libpython must be preloaded for the
Python type-support libraries the server opens.

Run ``python -m pmk_nb.robot.wheels`` to set up (the project venv runs it; it imports no ROS).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.errors import PmkError
from pmk_nb.fileio import atomic_write

# Built in this order (none depends on another). rosapi_msgs lets the server run with rosapi on.
INTERFACES = ("tf2_msgs", "nav2_msgs", "map_server_pmk", "rosapi_msgs")
STACK_VERSION = "2"  # bump when the steps below change

CHECKOUT = Path(__file__).resolve().parents[2]
INTERFACES_DIR = CHECKOUT / "ros" / "interfaces"
#: the stack's Python packages, pinned with hashes (`make lock` compiles requirements/ros2.in into it)
LOCK = CHECKOUT / "requirements" / "ros2.txt"


class StackMissing(PmkError, RuntimeError):
    """The ROS 2 wheels stack is not set up here; the message says what to run."""


def cache_dir() -> Path:
    return Path(os.environ.get("PMK_ROS_CACHE") or Path.home() / ".cache" / "pmk-ros")


@dataclass(frozen=True)
class Stack:
    """Where the set-up stack is and the environment its processes need."""

    root: Path
    python: Path
    server: Path
    env: dict[str, str]

    def process_env(self, domain_id: int, **extra: str) -> dict[str, str]:
        """The environment for a node or the server: loopback-only DDS on a private domain."""
        env = {k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "RMW_", "LD_", "_ROS_"))}
        env.update(self.env)
        env.update(ROS_DOMAIN_ID=str(domain_id), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", **extra)
        env["PYTHONPATH"] = os.pathsep.join(p for p in (str(CHECKOUT), env.get("PYTHONPATH", "")) if p)
        return env

    def node_env(self, domain_id: int) -> dict[str, str]:
        """For the venv's python: no preload (the wheels' bootstrap sets the library path itself)."""
        env = self.process_env(domain_id)
        env.pop("LD_PRELOAD", None)
        return env


def load(root: Path | None = None) -> Stack:
    """The stack set up by :func:`setup`.

    Raises:
        StackMissing: it is not set up, or is out of date for this checkout.
    """
    root = root or cache_dir()
    manifest = root / "stack.json"
    if not manifest.is_file():
        raise StackMissing(f"no ROS 2 stack at {root}: run `make ros2` (python -m pmk_nb.robot.wheels)")
    data = json.loads(manifest.read_text())
    built = data.get("interfaces") or {}
    stale = [name for name in INTERFACES if built.get(name) != _interface_stamp(name)]
    if data.get("stamp") != _venv_stamp() or stale:
        what = f" ({', '.join(stale)} changed)" if stale and data.get("stamp") == _venv_stamp() else ""
        raise StackMissing(f"the ROS 2 stack at {root} is out of date for this checkout{what}: run `make ros2`")
    return Stack(root, Path(data["python"]), Path(data["server"]), dict(data["env"]))


def _venv_stamp() -> str:
    """What the venv holds: changes here rebuild everything."""
    text = f"{STACK_VERSION} {sys.version_info[:2]} "
    return hashlib.sha256(text.encode() + LOCK.read_bytes()).hexdigest()[:16]


def _interface_stamp(name: str) -> str:
    """One interface package's files (and the venv it is built into)."""
    h = hashlib.sha256(_venv_stamp().encode())
    folder = INTERFACES_DIR / name
    for path in sorted(folder.rglob("*")):
        if path.is_file():
            h.update(str(path.relative_to(folder)).encode() + b"\0" + path.read_bytes())
    return h.hexdigest()[:16]


def _run(cmd: list[str], log: Path, **kw: object) -> None:
    with log.open("ab") as out:
        done = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, check=False, **kw)  # type: ignore[call-overload]
    if done.returncode != 0:
        tail = log.read_text(errors="replace")[-3000:]
        raise StackMissing(f"{' '.join(cmd[:4])} ... failed (exit {done.returncode}); log {log}:\n{tail}")


def _fix_cmake_paths(venv: Path, python: Path) -> int:
    """Point the wheels' exported Python/numpy include dirs at this venv's; returns files changed."""
    query = "import sysconfig, numpy; print(sysconfig.get_paths()['include']); print(numpy.get_include())"
    include, numpy_include = subprocess.run(
        [str(python), "-c", query], capture_output=True, text=True, check=True
    ).stdout.split()
    changed = 0
    for path in (venv / "share").rglob("*.cmake"):
        text = path.read_text(errors="replace")
        if "/opt/python/" not in text:
            continue
        text = re.sub(r"/opt/python/[^/]+/lib/python3\.\d+/site-packages/numpy/_core/include", numpy_include, text)
        text = re.sub(r"/opt/python/[^/]+/include/python3\.\d+", include, text)
        path.write_text(text)
        changed += 1
    return changed


def _libpython(python: Path) -> str:
    query = "import sysconfig as s, os; print(os.path.join(s.get_config_var('LIBDIR'), s.get_config_var('INSTSONAME')))"
    lib = subprocess.run([str(python), "-c", query], capture_output=True, text=True, check=True).stdout.strip()
    if not Path(lib).is_file():
        raise StackMissing(f"libpython not found at {lib}: the server's Python type support needs a shared libpython")
    return lib


def _runtime_env(venv: Path, python: Path) -> dict[str, str]:
    site = next((venv / "lib").glob("python3.*/site-packages"))
    shim = venv.parent / "rmw-shim"
    shim.mkdir(exist_ok=True)
    link = shim / "librmw_implementation.so"
    if not link.exists():
        link.symlink_to(venv / "lib" / "librmw_fastrtps_cpp.so")
    libs = [str(shim), str(venv / "lib"), *sorted(str(p) for p in site.glob("ros_*.libs"))]
    return {
        "ROS_DISTRO": "jazzy",
        "RMW_IMPLEMENTATION": "rmw_fastrtps_cpp",
        "AMENT_PREFIX_PATH": str(venv),
        "LD_LIBRARY_PATH": os.pathsep.join(libs),
        "LD_PRELOAD": _libpython(python),
        "PYTHONPATH": str(site),
    }


def _build_interface(name: str, venv: Path, build_root: Path, log: Path, clock: Clock = MONOTONIC) -> float:
    start = clock.now()
    build = build_root / name
    shutil.rmtree(build, ignore_errors=True)
    build.mkdir(parents=True)
    env = {**os.environ, "AMENT_PREFIX_PATH": str(venv), "CMAKE_PREFIX_PATH": str(venv)}
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    python = venv / "bin" / "python"
    _run(
        [
            "cmake",
            str(INTERFACES_DIR / name),
            f"-DCMAKE_INSTALL_PREFIX={venv}",
            "-DCMAKE_BUILD_TYPE=Release",
            "-DBUILD_TESTING=OFF",
            f"-DPython3_EXECUTABLE={python}",
        ],
        log,
        cwd=build,
        env=env,
    )
    _run(["cmake", "--build", ".", "-j", str(os.cpu_count() or 2)], log, cwd=build, env=env)
    _run(["cmake", "--install", "."], log, cwd=build, env=env)
    return clock.now() - start


def setup(root: Path | None = None, *, say=print, clock: Clock = MONOTONIC) -> Stack:  # type: ignore[no-untyped-def]
    """Set the stack up (instant when the stamps match; only changed interfaces are rebuilt); returns it.
    ``clock`` times the steps it reports."""
    root = root or cache_dir()
    try:
        return load(root)
    except StackMissing:
        pass
    start = clock.now()
    root.mkdir(parents=True, exist_ok=True)
    log = root / "setup.log"
    log.write_text("")
    manifest_path = root / "stack.json"
    manifest = json.loads(manifest_path.read_text()) if manifest_path.is_file() else {}
    venv = root / "venv"
    python = venv / "bin" / "python"
    if manifest.get("stamp") != _venv_stamp() or not python.exists():
        manifest = _make_venv(venv, log, say)
    manifest.setdefault("interfaces", {})
    for name in INTERFACES:
        stamp = _interface_stamp(name)
        if manifest["interfaces"].get(name) == stamp:
            continue
        seconds = _build_interface(name, venv, root / "build", log, clock)
        say(f"ROS 2 stack: built {name} in {seconds:.1f} s")
        manifest["interfaces"][name] = stamp
        atomic_write(manifest_path, json.dumps(manifest, indent=1))  # kept: a later failure keeps this one
    atomic_write(manifest_path, json.dumps(manifest, indent=1))
    say(f"ROS 2 stack: ready in {clock.now() - start:.0f} s")
    return load(root)


def _make_venv(venv: Path, log: Path, say) -> dict:  # type: ignore[no-untyped-def,type-arg]
    """A fresh venv with the wheels (from pip's cache when there); returns the manifest, no interfaces yet."""
    if venv.exists():
        shutil.rmtree(venv)  # out of date: start clean
    base = getattr(sys, "_base_executable", sys.executable)
    say(f"ROS 2 stack: venv at {venv}")
    _run([base, "-m", "venv", str(venv)], log)
    python = venv / "bin" / "python"
    pip = [str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]
    say("ROS 2 stack: installing the Jazzy wheels and the rosbridge server")
    _run([*pip, "--require-hashes", "-r", str(LOCK)], log)
    say(f"ROS 2 stack: fixed Python include paths in {_fix_cmake_paths(venv, python)} cmake files")
    server = next((venv / "lib").glob("python3.*/site-packages/rosbridge_server_rs/rosbridge_server_rs_jazzy"))
    server.chmod(server.stat().st_mode | 0o111)
    env = _runtime_env(venv, python)
    return {"stamp": _venv_stamp(), "python": str(python), "server": str(server), "env": env, "interfaces": {}}


def main() -> int:
    try:
        stack = setup()
    except StackMissing as err:
        print(f"make ros2: {err}", file=sys.stderr)
        return 1
    print(f"ROS 2 stack ready: {stack.root}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
