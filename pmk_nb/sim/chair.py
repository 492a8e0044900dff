"""The simulated wheelchair body: differential drive, collision stop, path following.

Manual ``/cmd_vel`` commands hold for ``cmd_timeout`` seconds (0.5 s, like a teleop watchdog) and
then the chair stops. A goal (``/move_base_simple/goal``) is followed with pure pursuit along a
planned path; a manual command given to the body cancels it (the engine decides whether a
``/cmd_vel`` reaches the body while a client's goal runs: with Nav2 or move_base it does not).
Collision: the chair's centre may not enter a cell of
the footprint-inflated blocked mask (occupied, unknown or off-map); the move is refused, linear
speed drops to zero (rotation in place is always possible for a round footprint) and ``bumped``
is set.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from pmk_nb.wire import wrap_angle as _wrap  # (-pi, pi]

if TYPE_CHECKING:
    from pmk_nb.sim.world import World


@dataclass(frozen=True)
class DriveLimits:
    v_max: float = 0.8  # m/s
    w_max: float = 1.2  # rad/s
    cmd_timeout: float = 0.5  # s without /cmd_vel before stopping
    lookahead: float = 0.35  # m, pure pursuit (short: doorways leave little room for corner cutting)
    goal_tolerance: float = 0.12  # m
    yaw_tolerance: float = 0.1  # rad
    stuck_timeout: float = 2.0  # s of refused moves (turning on the spot not counted) before a goal is given up


class Chair:
    """State and motion; ``step`` is called by the sim loop with the elapsed time."""

    def __init__(self, world: World, pose: tuple[float, float, float], limits: DriveLimits | None = None) -> None:
        self.world = world
        self.limits = limits or DriveLimits()
        self.pose = pose
        self.v = 0.0
        self.w = 0.0
        self.bumped = False
        self._cmd = (0.0, 0.0)
        self._cmd_time = -math.inf
        self._path: list[tuple[float, float]] = []
        self._goal_yaw: float | None = None
        self._k = 0
        self._stuck = 0.0  # s of refused moves since the last move that went ahead
        self.goal_status = "idle"  # idle | planning | active | reached | blocked | no_path | cancelled
        self.on_goal_done: Callable[[str], None] | None = None

    # -- inputs -----------------------------------------------------------------------------------

    def command(self, v: float, w: float, now: float) -> None:
        lim = self.limits
        self._cmd = (max(-lim.v_max, min(lim.v_max, v)), max(-lim.w_max, min(lim.w_max, w)))
        self._cmd_time = now
        if self._path:
            self._finish("cancelled")

    def follow(self, path: list[tuple[float, float]], goal_yaw: float | None) -> None:
        self._path, self._k, self._goal_yaw = _densify(path, 0.1), 0, goal_yaw
        self._stuck = 0.0
        self._cmd_time = -math.inf
        self.goal_status = "active" if path else "no_path"

    def stop_goal(self, *, quiet: bool = False) -> None:
        """Drop the goal and stop (a cancel); ``quiet`` skips ``on_goal_done`` (a new goal follows)."""
        self.v = self.w = 0.0
        self._cmd = (0.0, 0.0)
        if self._path:
            callback, self.on_goal_done = self.on_goal_done, (None if quiet else self.on_goal_done)
            try:
                self._finish("cancelled")
            finally:
                self.on_goal_done = callback
        elif not quiet:
            self.goal_status = "cancelled"

    def remaining_distance(self) -> float | None:
        """Metres left along the followed path (None when no path is being followed)."""
        path = self._path
        if not path:
            return None
        k = min(self._k, len(path) - 1)
        rest = sum(math.dist(path[i], path[i + 1]) for i in range(k, len(path) - 1))
        return math.dist(self.pose[:2], path[k]) + rest

    @property
    def driving_goal(self) -> bool:
        return bool(self._path)

    def path_ahead(self, length: float) -> list[tuple[float, float]]:
        """The next ``length`` metres of the followed path from the chair (empty without a goal): what a
        local planner would publish as its local plan."""
        path = self._path
        if not path:
            return []
        out = [(float(self.pose[0]), float(self.pose[1]))]
        gone = 0.0
        for point in path[min(self._k, len(path) - 1) :]:
            gone += math.dist(out[-1], point)
            out.append(point)
            if gone >= length:
                break
        return out

    def teleport(self, pose: tuple[float, float, float]) -> None:
        self.pose = pose
        self.v = self.w = 0.0
        if self._path:
            self._finish("cancelled")

    # -- motion -----------------------------------------------------------------------------------

    def step(self, dt: float, now: float) -> None:
        if dt <= 0:
            return
        if self._path:
            v, w = self._pursue()
        elif now - self._cmd_time <= self.limits.cmd_timeout:
            v, w = self._cmd
        else:
            v, w = 0.0, 0.0
        self.v, self.w = self._integrate(v, w, dt, slide=bool(self._path))
        if not self._path:
            return
        if v != 0.0 and self.v == 0.0:  # refused: recover along the path, give up after a while
            self._stuck += dt
            if self._stuck > self.limits.stuck_timeout:
                self._finish("blocked")
        elif self.v != 0.0:
            self._stuck = 0.0

    def _integrate(self, v: float, w: float, dt: float, *, slide: bool = False) -> tuple[float, float]:
        """Exact arc integration in sub-steps of at most half a cell; refuse moves into blocked space.

        ``slide``: a sub-step into blocked space keeps its part along one axis that stays free. A
        goal's controller keeps off walls (pure pursuit cutting a corner would otherwise pin the
        chair in it, seen as 0.5 % of goals aborted on the demo map); a manual command into a wall
        is refused.
        """
        half_cell = 0.5 * self.world.grid.resolution
        n = max(1, math.ceil(abs(v) * dt / half_cell))
        h = dt / n
        x, y, th = self.pose
        moved = v
        for _ in range(n):
            nth = th + w * h
            if abs(w) > 1e-9:
                nx = x + v / w * (math.sin(nth) - math.sin(th))
                ny = y - v / w * (math.cos(nth) - math.cos(th))
            else:
                nx, ny = x + v * h * math.cos(th), y + v * h * math.sin(th)
            if v != 0.0 and self.world.blocked_at(nx, ny):
                slid = self._slide(x, y, nx, ny) if slide else None
                if slid is None:
                    self.bumped = True
                    moved = 0.0
                    v = 0.0
                    nx, ny = x, y
                else:
                    nx, ny = slid
            x, y, th = nx, ny, nth
        self.pose = (x, y, _wrap(th))
        if moved != 0.0:
            self.bumped = False
        return moved, w

    def _slide(self, x: float, y: float, nx: float, ny: float) -> tuple[float, float] | None:
        """The free axis-aligned part of the sub-step (x, y) -> (nx, ny), or None."""
        for sx, sy in ((nx, y), (x, ny)):
            if math.hypot(sx - x, sy - y) > 1e-4 and not self.world.blocked_at(sx, sy):
                return sx, sy
        return None

    def _pursue(self) -> tuple[float, float]:
        lim = self.limits
        x, y, th = self.pose
        path = self._path
        if self.bumped:
            return self._recover()
        while self._k < len(path) - 1 and math.dist((x, y), path[self._k]) < lim.lookahead:
            self._k += 1
        tx, ty = path[self._k]
        end = path[-1]
        to_end = math.dist((x, y), end)
        if to_end < lim.goal_tolerance:
            if self._goal_yaw is None:
                self._finish("reached")
                return 0.0, 0.0
            err = _wrap(self._goal_yaw - th)
            if abs(err) < lim.yaw_tolerance:
                self._finish("reached")
                return 0.0, 0.0
            return 0.0, math.copysign(min(lim.w_max, max(0.3, abs(err) * 1.5)), err)
        alpha = _wrap(math.atan2(ty - y, tx - x) - th)
        if abs(alpha) > math.radians(60):
            return 0.0, math.copysign(lim.w_max, alpha)
        dist = max(math.dist((x, y), (tx, ty)), 1e-3)
        v = min(lim.v_max * (1.0 - 0.5 * abs(alpha) / math.radians(60)), 0.8 * to_end + 0.1)
        w = 2.0 * v * math.sin(alpha) / dist
        return v, max(-lim.w_max, min(lim.w_max, w))

    def _recover(self) -> tuple[float, float]:
        """After a refused move (corner cut too tight): face the path just ahead, then creep."""
        x, y, th = self.pose
        path = self._path
        near = min(range(len(path)), key=lambda i: math.dist((x, y), path[i]))
        tx, ty = path[min(near + 2, len(path) - 1)]
        alpha = _wrap(math.atan2(ty - y, tx - x) - th)
        if abs(alpha) > 0.25:
            return 0.0, math.copysign(min(self.limits.w_max, 1.0), alpha)
        return 0.15, 0.0

    def _finish(self, status: str) -> None:
        self._path = []
        self._goal_yaw = None
        self.goal_status = status
        if self.on_goal_done is not None:
            self.on_goal_done(status)


def _densify(path: list[tuple[float, float]], spacing: float) -> list[tuple[float, float]]:
    """Points every ``spacing`` metres along the polyline, so the lookahead point slides along it."""
    if len(path) < 2:
        return list(path)
    out = [path[0]]
    for (x0, y0), (x1, y1) in itertools.pairwise(path):
        n = max(1, math.ceil(math.dist((x0, y0), (x1, y1)) / spacing))
        out += [(x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * i / n) for i in range(1, n + 1)]
    return out
