"""SimChair: a simulated PMK wheelchair behind a rosbridge v2 WebSocket (and optionally SFTP).

It runs in a background thread with its own asyncio loop, so tests, notebooks and the CLI can use
it from plain synchronous code: ``SimChair(...).start()`` ... ``stop()``. Stopping and starting
again reuses the same port (reconnect tests); ``pause()`` stops all publishing while sockets stay
open (stale-data tests).
"""

from __future__ import annotations

import asyncio
import errno
import math
import shutil
import ssl
import tempfile
import threading
import weakref
from collections.abc import Callable, Coroutine
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np
from websockets.asyncio.server import Server, serve

from pmk_nb.errors import PmkError
from pmk_nb.grid import OccupancyGrid
from pmk_nb.sim.bridge_modes import BRIDGE_MODES
from pmk_nb.sim.chair import DriveLimits
from pmk_nb.sim.config import SimConfig
from pmk_nb.sim.demo import demo_grid
from pmk_nb.sim.engine import Engine
from pmk_nb.sim.laser import Laser
from pmk_nb.sim.mapserver import RELOAD_SERVICES, MapServer, image_reader
from pmk_nb.sim.messages import ROS_VERSIONS, Names
from pmk_nb.sim.paths import ChairFS
from pmk_nb.sim.protocol import Bridge
from pmk_nb.sim.rosapi import register_rosapi

if TYPE_CHECKING:
    import asyncssh  # loaded with the SFTP endpoint only

    from pmk_nb.sim.sftp import SftpEndpoint

T = TypeVar("T")


class SimError(PmkError):
    """The simulator could not start (port in use, bad map, bad option)."""


#: ``pmk sim``'s exit status when a port it was given is taken (``os.EX_TEMPFAIL``): a launcher that
#: picked the ports itself (``pmk demo``) picks others and starts it again; any other failure is 2.
PORT_IN_USE_EXIT = 75


class SimPortInUse(SimError):
    """A port the simulator was told to listen on is taken by another program.

    Attributes:
        host: the address it tried to listen on.
        port: the rosbridge port it was given (the taken one may be its SFTP port).
    """

    exit_code = PORT_IN_USE_EXIT

    def __init__(self, message: str, *, host: str, port: int) -> None:
        super().__init__(message, hint="choose other ports, or stop the program that holds this one")
        self.host, self.port = host, port


class SimChair:
    """A simulated chair. All public methods are thread-safe and callable from any thread."""

    def __init__(self, config: SimConfig | None = None) -> None:
        """``config``: every setting (:class:`~pmk_nb.sim.config.SimConfig`, defaults and meanings declared
        there), kept whole as :attr:`config` and read from it; checked here (:class:`SimError`)."""
        cfg = SimConfig() if config is None else config
        if not isinstance(cfg, SimConfig):
            raise SimError(f"SimChair takes a SimConfig, not {type(cfg).__name__}: SimChair(SimConfig(map_yaml=...))")
        _check(cfg)
        self.config = cfg
        self._port = cfg.port  # the port listened on: a free one once start() ran with port 0
        self.names = Names(cfg.ros)
        self.laser = Laser(rays=cfg.rays, range_max=cfg.range_max, blind=cfg.laser_blind)
        self._init_sftp(cfg)
        self._init_maps(cfg.maps_dir)
        self._thread: threading.Thread | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop_event: asyncio.Event | None = None
        self._error: BaseException | None = None
        self.mapserver: MapServer | None = None
        self.bridge: Bridge | None = None
        self.engine = Engine(
            self.names,
            self.laser,
            odom_rate=cfg.odom_rate,
            scan_rate=cfg.scan_rate,
            footprint_radius=cfg.footprint_radius,
            limits=cfg.limits or DriveLimits(),
            start_pose=cfg.start_pose,
            patrol=cfg.patrol,
            rng=np.random.default_rng(cfg.seed),
            clock=cfg.clock,
            wall=cfg.wall_clock,
        )
        self.engine.navigator.offer_actions = cfg.nav_actions
        # the certificate served from the next start (tests swap it between starts)
        self.tls = (Path(cfg.tls[0]), Path(cfg.tls[1])) if cfg.tls is not None else None

    def _init_sftp(self, cfg: SimConfig) -> None:
        """The SFTP login: the password (a random one when none is given) and the authorized keys, read now
        so a bad key fails before start()."""
        # None = password login refused (key only)
        self.sftp_password: str | None = (cfg.sftp_password or _random_password()) if cfg.sftp_password_login else None
        self.sftp_keys: list[asyncssh.SSHKey] = []
        if cfg.sftp_authorized_key is not None:
            from pmk_nb.sim.sftp import load_authorized_keys

            try:
                self.sftp_keys = load_authorized_keys(cfg.sftp_authorized_key)
            except ValueError as err:
                raise SimError(str(err)) from err
        self.sftp_port: int | None = None  # the port listened on, once started
        self.sftp_host_key_fingerprint: str | None = None  # "SHA256:..." as OpenSSH prints it
        self.sftp_host_key: str | None = None  # OpenSSH public key line, for known_hosts
        self.sftp_server_key: asyncssh.SSHKey | None = None

    def _init_maps(self, maps_dir: Path | str | None) -> None:
        """The chair's ALMA_MAPS folder (a temporary one, removed with the object, if none given)."""
        if maps_dir is None:
            maps_dir = tempfile.mkdtemp(prefix="pmk-sim-maps-")
            self._cleanup = weakref.finalize(self, shutil.rmtree, maps_dir, True)
        self.maps_dir = Path(maps_dir)
        self.maps_dir.mkdir(parents=True, exist_ok=True)
        self.fs = ChairFS(self.maps_dir, self.config.sftp_user)

    # -- lifecycle --------------------------------------------------------------------------------

    @property
    def port(self) -> int:
        return self._port

    @property
    def url(self) -> str:
        return f"{'wss' if self.tls else 'ws'}://{self.config.host}:{self._port}"

    @property
    def sftp_authorized_fingerprints(self) -> list[str]:
        """Fingerprints ("SHA256:...") of the public keys allowed to log in over SFTP (empty: none)."""
        return [key.get_fingerprint("sha256") for key in self.sftp_keys]

    @property
    def running(self) -> bool:
        return self._thread is not None and self._thread.is_alive()

    def start(self, timeout: float = 10.0) -> SimChair:
        """Serve in a background thread; returns once the port accepts connections."""
        if self.running:
            return self
        grid = self._first_grid()
        ready = threading.Event()
        self._error = None
        self._thread = threading.Thread(target=self._run, args=(grid, ready), name="pmk-sim", daemon=True)
        self._thread.start()
        if not ready.wait(timeout):
            self.stop()
            raise SimError(f"simulator did not start within {timeout} s")
        if self._error is not None:
            self._thread.join(timeout)
            err = self._error
            message = f"simulator could not start on {self.config.host}:{self._port}: {err}"
            if isinstance(err, OSError) and err.errno == errno.EADDRINUSE:
                raise SimPortInUse(message, host=self.config.host, port=self._port) from err
            raise SimError(message) from err
        return self

    def stop(self, timeout: float = 10.0) -> None:
        """Close every connection and the listening sockets; the object can be started again."""
        loop, thread = self._loop, self._thread
        if loop is not None and thread is not None and thread.is_alive() and self._stop_event is not None:
            loop.call_soon_threadsafe(self._stop_event.set)
            thread.join(timeout)
        self._thread = None

    def __enter__(self) -> SimChair:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def pause(self) -> None:
        """Stop publishing and moving (sockets and services stay up): clients see stale data."""
        self.engine.paused = True

    def resume(self) -> None:
        self.engine.paused = False

    @property
    def paused(self) -> bool:
        return self.engine.paused

    # -- state and control from other threads -----------------------------------------------------

    @property
    def pose(self) -> tuple[float, float, float]:
        """Ground truth (x, y, theta) in the map frame (= odom frame: map->odom is identity)."""
        chair = self.engine.chair
        return chair.pose if chair else (math.nan, math.nan, math.nan)

    @property
    def velocity(self) -> tuple[float, float]:
        chair = self.engine.chair
        return (chair.v, chair.w) if chair else (0.0, 0.0)

    @property
    def bumped(self) -> bool:
        return bool(self.engine.chair and self.engine.chair.bumped)

    @property
    def goal_status(self) -> str:
        return self.engine.chair.goal_status if self.engine.chair else "idle"

    @property
    def grid(self) -> OccupancyGrid | None:
        return self.mapserver.grid if self.mapserver else None

    @property
    def patrol(self) -> bool:
        """Patrol mode: drive between random reachable points while nobody drives manually."""
        return self.engine.patrol

    @patrol.setter
    def patrol(self, on: bool) -> None:
        self.engine.patrol = bool(on)

    @property
    def notes(self) -> list[str]:
        """Things the simulator did on its own (e.g. moved the chair off a wall after a reload)."""
        return self.engine.notes

    @property
    def client_count(self) -> int:
        return len(self.bridge.clients) if self.bridge else 0

    def mark_obstacle(self, x: float, y: float, radius: float = 0.25) -> int:
        """Something the map does not have at (x, y), as the global costmap's obstacle layer marks it: the
        next costmap patch (``<global costmap>_updates``) carries it. Returns the cells marked."""
        return self.engine.layers.mark(x, y, radius)

    def set_pose(self, x: float, y: float, theta: float = 0.0) -> None:
        self._call(self.engine.teleport, (x, y, theta))

    def drive(self, v: float, w: float, timeout: float = 10.0) -> None:
        """A ``/cmd_vel`` (m/s, rad/s) as a client's, taken before this returns: a test on a virtual
        clock (``SimConfig.clock``) then knows at which instant the command holds from."""

        async def command() -> None:
            self.engine.on_cmd_vel({"linear": {"x": v}, "angular": {"z": w}})

        self._run_coro(command(), timeout)

    def load_map(self, path: str | Path, timeout: float = 30.0) -> int:
        """Reload like a service call would; returns the Nav2 result code (0 = success)."""
        assert self.mapserver is not None, "start() the simulator first"
        code, _ = self._run_coro(self.mapserver.load(str(path)), timeout)
        return int(code)

    def disconnect_clients(self, timeout: float = 5.0) -> None:
        """Close every client connection (the server keeps listening): for reconnect tests."""
        if self.bridge is not None:
            self._run_coro(self.bridge.close_all(), timeout)

    def _call(self, fn: Callable[..., object], *args: object) -> None:
        if self._loop is None or not self.running:
            raise SimError("the simulator is not running")
        self._loop.call_soon_threadsafe(fn, *args)

    def _run_coro(self, coro: Coroutine[Any, Any, T], timeout: float) -> T:
        if self._loop is None or not self.running:
            coro.close()
            raise SimError("the simulator is not running")
        return asyncio.run_coroutine_threadsafe(coro, self._loop).result(timeout)

    # -- the loop thread --------------------------------------------------------------------------

    def _first_grid(self) -> OccupancyGrid:
        if self.mapserver is not None and self.mapserver.grid is not None:
            return self.mapserver.grid  # restart keeps the current map
        if self.config.grid is not None:
            return self.config.grid
        if self.config.map_yaml is not None:
            from pmk_nb.rosmap import read_map

            return read_map(Path(self.config.map_yaml), reader=image_reader(self.config.ros))
        return demo_grid()

    def _run(self, grid: OccupancyGrid, ready: threading.Event) -> None:
        loop = asyncio.new_event_loop()
        self._loop = loop
        try:
            loop.run_until_complete(self._main(grid, ready))
        except BaseException as err:
            self._error = err
        finally:
            ready.set()
            loop.run_until_complete(loop.shutdown_default_executor())  # map-load / planning threads
            loop.close()

    async def _main(self, grid: OccupancyGrid, ready: threading.Event) -> None:
        self._stop_event = asyncio.Event()
        cfg = self.config
        bridge = Bridge(cfg.client_queue, cfg.bridge, action_ops=cfg.ros == "ros2", auth_secret=cfg.auth_secret)
        self.bridge = bridge
        first = Path(cfg.map_yaml) if cfg.map_yaml is not None else None
        source = self.mapserver.source if self.mapserver else first
        self.mapserver = MapServer(bridge, self.names, self.fs, self.engine.install, cfg.reload_services)
        self.mapserver.register()
        register_rosapi(bridge, self.names, self.engine.wall.now)
        self.engine.attach(bridge)
        await self.mapserver.set_grid(grid, source)
        # SFTP listens before rosbridge does: whoever finds rosbridge listening (pmk demo waits on it, then
        # on SFTP) finds our SFTP server too, never another program that took its port meanwhile
        sftp: SftpEndpoint | None = None
        if cfg.sftp_port is not None:
            from pmk_nb.sim.sftp import start_sftp

            sftp = await start_sftp(self)
        try:
            server = await serve(
                bridge.handle,
                cfg.host,
                self._port,
                compression=None,
                max_size=16 * 2**20,
                reuse_address=True,
                ssl=self._server_tls(),
            )
        except BaseException:
            if sftp is not None:
                sftp.close()
                await sftp.wait_closed()
            raise
        try:
            self._port = int(next(iter(server.sockets)).getsockname()[1])
            tasks = self.engine.tasks()
            ready.set()
            await self._stop_event.wait()
            for task in tasks:
                task.cancel()
        finally:
            await self._shutdown(server, bridge, sftp)

    def _server_tls(self) -> ssl.SSLContext | None:
        """The TLS context of ``wss://`` (read at each start: a test swaps the certificate between starts)."""
        if self.tls is None:
            return None
        ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
        ctx.load_cert_chain(str(self.tls[0]), str(self.tls[1]))
        return ctx

    async def _shutdown(self, server: Server, bridge: Bridge, sftp: SftpEndpoint | None) -> None:
        server.close(close_connections=False)
        await bridge.close_all()
        await server.wait_closed()
        if sftp is not None:
            sftp.close()
            await sftp.wait_closed()
        self.engine.cancel_plan()


def _check(cfg: SimConfig) -> None:
    """Refuse a setting the simulator cannot honour, before anything starts."""
    if cfg.ros not in ROS_VERSIONS:
        raise SimError(f"unknown ROS version {cfg.ros!r}: use 'ros1' or 'ros2'")
    if cfg.bridge not in BRIDGE_MODES:
        raise SimError(f"unknown bridge {cfg.bridge!r}: use one of {', '.join(BRIDGE_MODES)}")
    if cfg.odom_rate <= 0 or cfg.scan_rate <= 0:
        raise SimError(f"rates must be positive (odom_rate={cfg.odom_rate}, scan_rate={cfg.scan_rate})")
    if not cfg.sftp_password_login and (cfg.sftp_authorized_key is None or cfg.sftp_password):
        raise SimError(
            "SFTP password login off needs an authorized key and no password "
            f"(sftp_authorized_key={cfg.sftp_authorized_key!r}, sftp_password given: {bool(cfg.sftp_password)})"
        )
    unknown = [s for s in cfg.reload_services or () if s not in RELOAD_SERVICES]
    if unknown:
        raise SimError(f"unknown reload service(s) {unknown}: choose from {', '.join(RELOAD_SERVICES)}")


def _random_password() -> str:
    import secrets

    return secrets.token_urlsafe(12)
