"""What runs on the simulator's loop: the chair in its world, goals, patrol and the publish loops.

The engine outlives a single server start: stopping and starting a SimChair attaches a fresh
bridge to the same engine, so the chair keeps its pose and map across restarts.

Time is an input (issue 39): ``clock`` runs the physics and the loops' rates (a ``VirtualClock`` in
tests: the chair then steps exactly at the ticks of the advanced span), ``wall`` stamps the messages.
"""

from __future__ import annotations

import asyncio
import logging
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from pmk_nb.clock import MONOTONIC, WALL, AsyncPacer, Clock
from pmk_nb.sim.chair import Chair, DriveLimits
from pmk_nb.sim.navigation import Navigator
from pmk_nb.sim.navlayers import SimNavLayers
from pmk_nb.sim.world import World

if TYPE_CHECKING:
    import numpy as np

    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.sim.laser import Laser
    from pmk_nb.sim.messages import Names
    from pmk_nb.sim.protocol import Bridge

LOG = logging.getLogger("pmk_nb.sim")
PATROL_IDLE = 5.0  # s after a manual command before patrol resumes
PATROL_PAUSE = 1.0  # s between patrol legs
PLAN_REPEAT_S = 1.0  # s between publishes of the plan being followed


class Engine:
    """Chair + world + loops. Every method runs on the simulator's event loop."""

    def __init__(
        self,
        names: Names,
        laser: Laser,
        *,
        odom_rate: float,
        scan_rate: float,
        footprint_radius: float,
        limits: DriveLimits,
        start_pose: tuple[float, float, float] | None,
        patrol: bool,
        rng: np.random.Generator,
        clock: Clock = MONOTONIC,
        wall: Clock = WALL,
    ) -> None:
        self.names = names
        self.clock, self.wall = clock, wall
        self.laser = laser
        self.odom_rate = odom_rate
        self.scan_rate = scan_rate
        self.footprint_radius = footprint_radius
        self.limits = limits
        self.start_pose = start_pose
        self.patrol = patrol
        self.rng = rng
        self.paused = False
        self.chair: Chair | None = None
        self.world: World | None = None
        self.bridge: Bridge | None = None
        self.notes: list[str] = []  # things the sim did on its own (moved the chair after a reload, ...)
        self._plan_task: asyncio.Task[None] | None = None
        self._last_manual = -math.inf
        self._patrol_next = 0.0
        self._plan_msg: dict[str, Any] | None = None  # the path being followed, as nav_msgs/Path
        self._plan_sent = -math.inf
        #: the header stamp (wall clock) of the chair's pose: odometry and tf carry it, and a scan cast
        #: from that pose carries it too (a laser stamps the instant it measured, not when it sends)
        self.pose_stamp: float | None = None
        self.navigator = Navigator(self)
        self.layers = SimNavLayers(names, footprint_radius)  # costmaps, footprint, local plan, markers
        self._layers_task: asyncio.Task[None] | None = None

    def attach(self, bridge: Bridge) -> None:
        """Register the chair's topics on a (new) bridge."""
        self.bridge = bridge
        n = self.names
        bridge.advertise_internal("/odom", n.msg("nav_msgs", "Odometry"))
        bridge.advertise_internal("/scan", n.msg("sensor_msgs", "LaserScan"))
        bridge.advertise_internal("/tf", n.msg("tf2_msgs", "TFMessage"))
        bridge.advertise_internal(n.plan_topic, n.msg("nav_msgs", "Path"))  # the global plan, as Nav2 does
        bridge.listen("/cmd_vel", n.msg("geometry_msgs", "Twist"), self.on_cmd_vel)
        self.navigator.attach(bridge)  # goal topics and actions
        self.layers.attach(bridge)

    def tasks(self) -> list[asyncio.Task[None]]:
        return [asyncio.create_task(self._odom_loop()), asyncio.create_task(self._scan_loop()), self.navigator.task()]

    def cancel_plan(self) -> None:
        if self._plan_task is not None:
            self._plan_task.cancel()
            self._plan_task = None

    def goal_ended(self) -> None:
        """A client's goal ended: patrol waits as after a manual command (a cancel must stay stopped)."""
        self._last_manual = self.clock.now()

    def note(self, text: str) -> None:
        LOG.info("sim: %s", text)
        self.notes.append(text)

    # -- map changes ------------------------------------------------------------------------------

    async def install(self, grid: OccupancyGrid) -> None:
        """Swap in a new map (built off the loop); keep the chair where it is if that is free.

        Only O(1) work happens on the loop; the chair keeps driving on the old map meanwhile.
        """
        world = await asyncio.to_thread(World, grid, self.footprint_radius)
        if not world.has_free:  # refuse before swapping anything: the chair keeps the old map
            raise ValueError("the map has no free cell large enough for the chair's footprint")
        self.cancel_plan()
        if self.chair is None:
            pose = self.start_pose
            if pose is None:
                x, y = await asyncio.to_thread(world.open_spot)
                pose = (x, y, 0.0)
            self.chair = Chair(world, pose, self.limits)
        else:
            self.chair.world = world
            self.chair.teleport(self.chair.pose)  # a new map cancels any goal
        self.world = world
        if self._layers_task is not None:
            self._layers_task.cancel()
        self._layers_task = asyncio.get_running_loop().create_task(self._build_layers(world))
        x, y, _ = self.chair.pose
        if world.blocked_at(x, y):  # stuck: every move into blocked space is refused meanwhile
            spot = await asyncio.to_thread(world.nearest_free, x, y)
            if spot is not None and self.world is world and self.chair.pose[:2] == (x, y):
                self.chair.teleport((spot[0], spot[1], self.chair.pose[2]))
                moved = f"moved to ({spot[0]:.2f}, {spot[1]:.2f})"
                self.note(f"pose ({x:.2f}, {y:.2f}) is not free on the new map: {moved}")

    async def _build_layers(self, world: World) -> None:
        """The costmaps of a new map, built off the loop; the map is installed without waiting for them."""
        costs, msg = await asyncio.to_thread(self.layers.build, world.grid, self.wall.now())
        if world is self.world:
            self.layers.use(world.grid, costs, msg)

    def teleport(self, pose: tuple[float, float, float]) -> None:
        self.cancel_plan()
        if self.chair is not None:
            self.chair.teleport(pose)

    # -- inputs -----------------------------------------------------------------------------------

    def on_cmd_vel(self, msg: dict[str, Any]) -> None:
        """A velocity command from a client. While a client's goal runs on a chair with Nav2 or
        move_base, it changes nothing: their controllers keep publishing (Nav2's controller_server
        at 20 Hz, move_base at ``controller_frequency``), so a command from elsewhere is overwritten
        at the next cycle and the goal runs on; only a cancel ends it. A patrol leg (the simulator's
        own demo) and a goal-topic follower without action servers yield to it, as a teleop would."""
        if self.chair is None:
            return
        lin, ang = msg.get("linear") or {}, msg.get("angular") or {}
        now = self.clock.now()
        self._last_manual = now
        nav = self.navigator
        if nav.current is not None and nav.offer_actions:
            return  # the navigation stack's controller wins (see above)
        self.cancel_plan()
        self.chair.command(float(lin.get("x", 0.0)), float(ang.get("z", 0.0)), now)

    def start_plan(self, goal: tuple[float, float], yaw: float | None, via: Sequence[tuple[float, float]] = ()) -> None:
        """Plan (off the loop) through ``via`` to ``goal`` and follow; ``goal_status`` is "planning" meanwhile."""
        self.cancel_plan()
        if self.chair is not None:
            self.chair.stop_goal(quiet=True)
            self.chair.goal_status = "planning"
        self._plan_task = asyncio.get_running_loop().create_task(self._plan(goal, yaw, via))

    @property
    def planning(self) -> bool:
        return self._plan_task is not None and not self._plan_task.done()

    async def _plan(
        self, goal: tuple[float, float], yaw: float | None, via: Sequence[tuple[float, float]] = ()
    ) -> None:
        chair, world = self.chair, self.world
        if chair is None or world is None:
            return
        path: list[tuple[float, float]] = []
        start = chair.pose[:2]
        for point in [*via, goal]:  # legs in order; one unreachable leg means no path
            leg = await asyncio.to_thread(world.plan, start, point)
            if not leg:
                path = []
                break
            path += leg[1:] if path else leg
            start = point
        if world is self.world:
            chair.follow(path, yaw)
            if not path:
                self.note(f"no path to goal ({goal[0]:.2f}, {goal[1]:.2f})")
            self._plan_msg = (
                self.names.path([(float(x), float(y)) for x, y in path], yaw, self.wall.now()) if path else None
            )
            self._plan_sent = -math.inf
            self._send_plan(self.clock.now())

    def _send_plan(self, now: float) -> None:
        """Publish the plan being followed, again every ``PLAN_REPEAT_S`` while the chair drives it
        (Nav2's navigator replans at 1 Hz and publishes each plan on /plan)."""
        chair, bridge, msg = self.chair, self.bridge, self._plan_msg
        if msg is None or chair is None or bridge is None or now - self._plan_sent < PLAN_REPEAT_S:
            return
        if not chair.driving_goal:
            self._plan_msg = None
            return
        self._plan_sent = now
        bridge.publish(self.names.plan_topic, msg)

    def _patrol_tick(self, chair: Chair, now: float) -> None:
        busy = chair.driving_goal or self.planning or self.navigator.current is not None
        if busy or now - self._last_manual < PATROL_IDLE or now < self._patrol_next or self.world is None:
            return
        self._patrol_next = now + PATROL_PAUSE
        self.cancel_plan()
        self._plan_task = asyncio.get_running_loop().create_task(self._patrol_leg())

    async def _patrol_leg(self) -> None:
        """Pick a reachable point and drive there; both searches run off the loop."""
        chair, world = self.chair, self.world
        if chair is None or world is None:
            return
        points = await asyncio.to_thread(world.reachable_points, chair.pose[:2], self.rng)
        if points and world is self.world:
            await self._plan(points[0], None)

    # -- loops ------------------------------------------------------------------------------------

    async def _odom_loop(self) -> None:
        """Physics and /odom + /tf at ``odom_rate`` (absolute schedule, no drift, no catch-up bursts)."""
        clock, pacer = self.clock, AsyncPacer(self.clock)
        period = 1.0 / self.odom_rate
        last = next_t = clock.now()
        seq = 0
        n = self.names
        while True:
            next_t += period
            await pacer.sleep(max(0.0, next_t - clock.now()))
            now = clock.now()
            next_t = max(next_t, now - period)
            dt, last = now - last, now
            chair, bridge = self.chair, self.bridge
            if self.paused or chair is None or bridge is None:
                continue
            chair.step(dt, now)
            self._send_plan(now)
            if self.patrol:
                self._patrol_tick(chair, now)
            seq += 1
            t = self.pose_stamp = self.wall.now()
            if bridge.has_subscribers("/odom"):
                bridge.publish("/odom", n.odometry(chair.pose, chair.v, chair.w, t, seq))
            if bridge.has_subscribers("/tf"):
                identity = n.transform("map", "odom", (0.0, 0.0, 0.0), t)
                bridge.publish("/tf", n.tf_message([identity, n.transform("odom", "base_link", chair.pose, t)]))
            self.layers.tick(bridge, chair, now, t)

    async def _scan_loop(self) -> None:
        """Ray cast and publish /scan at ``scan_rate``, only while someone listens."""
        clock, pacer = self.clock, AsyncPacer(self.clock)
        period = 1.0 / self.scan_rate
        next_t = clock.now()
        seq = 0
        lz = self.laser
        cast: tuple[object, ...] | None = None  # what the last cast saw: a parked chair's scan is the same
        ranges: np.ndarray | None = None
        while True:
            next_t += period
            await pacer.sleep(max(0.0, next_t - clock.now()))
            next_t = max(next_t, clock.now() - period)
            chair, world, bridge = self.chair, self.world, self.bridge
            if self.paused or chair is None or world is None or bridge is None:
                continue
            if not bridge.has_subscribers("/scan"):
                continue
            grid = world.grid
            seen = (world, tuple(float(v) for v in chair.pose), lz.blind, lz.rays, lz.range_max)
            if seen != cast:  # a World compares by identity: its masks never change in place (a new map is a new World)
                ranges = lz.cast(world.hit, grid.resolution, grid.origin[:2], chair.pose)
                cast = seen
            assert ranges is not None
            seq += 1
            stamp = self.pose_stamp if self.pose_stamp is not None else self.wall.now()  # the pose it was cast from
            msg = self.names.laser_scan(
                ranges, lz.angle_min, lz.angle_increment, lz.range_min, lz.range_max, period, stamp, seq
            )
            bridge.publish("/scan", msg)
