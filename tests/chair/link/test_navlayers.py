"""The navigation stack's layers (issue 40): costmaps with their updates, footprint, local plan and
markers, found by type through rosapi and followed on the simulated chair (which publishes them as Nav2
and move_base name them)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from pmk_nb.chair.link.streams.navlayers import (
    FOOTPRINT,
    GLOBAL,
    LAYERS,
    LOCAL,
    LOCAL_PLAN,
    MARKERS,
    BadLayerMessage,
    CostmapUpdateOutside,
    MarkerBoard,
    NavLayerWatch,
    apply_update,
    parse_costmap,
    parse_footprint,
    parse_markers,
    pick_topics,
)
from pmk_nb.sim.navlayers import INSCRIBED, LETHAL, inflated_costs
from pmk_nb.viewport.markers import ARROW, LINE_STRIP
from tests.fixtures_sim import room_grid, wait_until


def grid_msg(width: int, height: int, data: list[int], frame: str = "map") -> dict[str, Any]:
    return {
        "header": {"frame_id": frame, "stamp": {"sec": 1, "nanosec": 0}},
        "info": {
            "width": width,
            "height": height,
            "resolution": 0.1,
            "origin": {"position": {"x": 1.0, "y": 2.0, "z": 0.0}, "orientation": {"z": 0.0, "w": 1.0}},
        },
        "data": data,
    }


def test_a_costmap_and_its_update_patches() -> None:
    costmap = parse_costmap(grid_msg(3, 2, [0, 50, 100, -1, 99, 0], frame="/odom"), "/local_costmap/costmap")
    assert costmap.data.tolist() == [[0, 50, 100], [-1, 99, 0]] and costmap.frame == "odom"
    assert costmap.origin == pytest.approx((1.0, 2.0, 0.0)) and costmap.resolution == pytest.approx(0.1)
    patched = apply_update(costmap, {"x": 1, "y": 1, "width": 2, "height": 1, "data": [7, 8]})
    assert patched.data.tolist() == [[0, 50, 100], [-1, 7, 8]] and patched.version == costmap.version + 1
    assert costmap.data.tolist()[1] == [-1, 99, 0]  # the old value is untouched
    assert apply_update(patched, {"x": 1, "y": 1, "width": 2, "height": 1, "data": [7, 8]}) is patched  # no change
    with pytest.raises(CostmapUpdateOutside) as err:
        apply_update(costmap, {"x": 2, "y": 0, "width": 2, "height": 1, "data": [1, 2]})
    assert err.value.patch == (2, 0, 2, 1) and err.value.size == (3, 2)
    with pytest.raises(BadLayerMessage) as bad:
        parse_costmap(grid_msg(3, 2, [0, 0]), "/global_costmap/costmap")
    assert bad.value.field == "data"


def test_footprint_and_markers_are_read_in_the_plane() -> None:
    fp = parse_footprint(
        {"header": {"frame_id": "odom"}, "polygon": {"points": [{"x": 1, "y": 0, "z": 0}, {"x": 0, "y": 1}]}}, "/fp"
    )
    assert fp.points.tolist() == [[1.0, 0.0], [0.0, 1.0]] and fp.frame == "odom"
    q = {"z": math.sin(0.25), "w": math.cos(0.25)}
    changes = parse_markers(
        {
            "markers": [
                {"ns": "a", "id": 1, "type": LINE_STRIP, "points": [{"x": 0, "y": 0}, {"x": 1, "y": 1}]},
                {"ns": "a", "id": 2, "type": ARROW, "pose": {"position": {"x": 2, "y": 3}, "orientation": q}},
                "not a marker",
            ]
        },
        "/m",
    )
    board = MarkerBoard()
    board.apply(changes)
    assert set(board.shown) == {("/m", "a", 1), ("/m", "a", 2)}
    assert board.shown[("/m", "a", 2)][1].pose == pytest.approx((2.0, 3.0, 0.5))
    board.apply(parse_markers({"markers": [{"ns": "a", "id": 1, "action": 2}]}, "/m"))
    assert set(board.shown) == {("/m", "a", 2)}
    board.apply(parse_markers({"markers": [{"action": 3}]}, "/other"))  # DELETEALL of another topic
    assert set(board.shown) == {("/m", "a", 2)}
    board.apply(parse_markers({"markers": [{"action": 3}]}, "/m"))
    assert board.shown == {}


def test_topics_are_picked_by_nav2_and_move_base_names_among_those_of_the_type() -> None:
    nav2 = pick_topics(
        {
            "nav_msgs/OccupancyGrid": ["/map", "/global_costmap/costmap", "/local_costmap/costmap"],
            "geometry_msgs/PolygonStamped": [
                "/global_costmap/published_footprint",
                "/local_costmap/published_footprint",
            ],
            "nav_msgs/Path": ["/plan", "/local_plan"],
            "visualization_msgs/MarkerArray": ["/waypoints"],
        }
    )
    assert nav2 == {
        GLOBAL: ("/global_costmap/costmap",),
        LOCAL: ("/local_costmap/costmap",),
        FOOTPRINT: ("/local_costmap/published_footprint",),
        LOCAL_PLAN: ("/local_plan",),
        MARKERS: ("/waypoints",),
    }
    ros1 = pick_topics(
        {
            "nav_msgs/OccupancyGrid": ["/map", "/move_base/global_costmap/costmap"],
            "geometry_msgs/PolygonStamped": ["/move_base/local_costmap/footprint"],
            "nav_msgs/Path": ["/move_base/DWAPlannerROS/local_plan", "/move_base/NavfnROS/plan"],
        }
    )
    assert ros1[GLOBAL] == ("/move_base/global_costmap/costmap",) and ros1[LOCAL] == ()
    assert ros1[FOOTPRINT] == ("/move_base/local_costmap/footprint",) and ros1[MARKERS] == ()
    assert ros1[LOCAL_PLAN] == ("/move_base/DWAPlannerROS/local_plan",)
    with pytest.raises(ValueError):
        NavLayerWatch(lambda _t: []).want("everything", True)


def test_inflation_has_lethal_walls_an_inscribed_band_and_decaying_costs() -> None:
    grid = room_grid(3.0, 3.0, resolution=0.05)
    costs = inflated_costs(grid, inscribed_m=0.3)
    assert (costs[np.asarray(grid.data) == 100] == LETHAL).all()
    row = costs[30]  # across the room, 1.5 m up: walls at both ends
    assert row[3] == INSCRIBED  # 0.15 m from the wall: inside the chair's radius
    assert 0 < row[8] < INSCRIBED and row[8] > row[10]  # 0.4 m, 0.5 m: lower further out
    assert row[30] == 0  # the middle: free


@pytest.mark.slow
@pytest.mark.parametrize("ros", ["ros2", "ros1"])
def test_the_simulated_chair_publishes_every_layer_and_the_watch_follows_it(
    ros: str, sim_factory: Callable[..., Any], link_factory: Callable[[Any], Any]
) -> None:
    grid = room_grid(8.0, 5.0, resolution=0.05)
    sim = sim_factory(grid=grid, ros=ros, start_pose=(1.5, 2.5, 0.0), footprint_radius=0.4)
    link = link_factory(sim)
    looked: list[str] = []

    def lookup(type_name: str) -> list[str]:
        looked.append(type_name)
        return link.topics_of_type(type_name)

    watch = NavLayerWatch(lookup)
    for layer in LAYERS:
        watch.want(layer, True)
    assert wait_until(lambda: bool(watch.follow(link.ros) or watch.subscribed.get(GLOBAL)), 15.0, 0.1)
    assert "map_msgs/OccupancyGridUpdate" in looked  # the updates topics are looked up, never guessed
    assert wait_until(lambda: bool(watch.follow(link.ros) or (watch.costmap(GLOBAL) and watch.footprint())), 15, 0.1)
    global_map = watch.costmap(GLOBAL)
    # republished unchanged every 5 s: the same costmap, not a new version to draw (and send) again
    seen = watch.counts[GLOBAL]
    assert wait_until(lambda: bool(watch.follow(link.ros) or watch.counts[GLOBAL] > seen), 15, 0.1)
    assert watch.costmap(GLOBAL) is global_map
    assert global_map is not None and global_map.data.shape == grid.data.shape and global_map.frame == "map"
    assert (global_map.data[np.asarray(grid.data) == 100] == LETHAL).all() and (global_map.data == INSCRIBED).any()
    assert wait_until(lambda: watch.costmap(LOCAL) is not None, 10, 0.1)
    local = watch.costmap(LOCAL)
    assert local is not None and local.frame == "odom" and local.data.shape == (80, 80)  # 4 m at 0.05 m
    footprint = watch.footprint()
    assert footprint is not None
    radii = np.hypot(footprint.points[:, 0] - 1.5, footprint.points[:, 1] - 2.5)
    assert footprint.points.shape[0] >= 8 and radii == pytest.approx(np.full(radii.shape, 0.4), abs=0.01)
    handle = link.navigate_to(6.5, 2.5, 0.0)
    assert wait_until(lambda: bool(watch.follow(link.ros) or watch.local_plan()), 15, 0.1)
    plan = watch.local_plan()
    assert plan is not None and plan.points.shape[0] >= 2
    assert wait_until(lambda: len(watch.markers()[1]) >= 5, 15, 0.1)
    kinds = {marker.kind for _frame, marker in watch.markers()[1]}
    assert kinds == {0, 4, 5, 8, 9}
    handle.cancel()
    watch.want(GLOBAL, False)
    watch.follow(link.ros)
    assert GLOBAL not in watch.subscribed and watch.costmap(GLOBAL) is None  # off: unsubscribed, forgotten
    watch.stop()


@pytest.mark.slow
def test_between_whole_costmaps_the_simulator_sends_patches_as_nav2_does(
    sim_factory: Callable[..., Any], link_factory: Callable[[Any], Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Something the map lacks, 1.5 m ahead of the chair, reaches the dashboard as a patch on the
    updates topic (Nav2's ``always_send_full_costmap: false``): with the whole costmap never repeated,
    the patch is the only way; the unchanged window's patches make no new version to draw."""
    from pmk_nb.sim import navlayers as sim_layers

    monkeypatch.setattr(sim_layers, "GLOBAL_REPEAT_S", 3600.0)  # the whole costmap once, to the new subscriber
    grid = room_grid(8.0, 5.0, resolution=0.05)
    sim = sim_factory(grid=grid, ros="ros2", start_pose=(1.5, 2.5, 0.0), footprint_radius=0.4)
    link = link_factory(sim)
    watch = NavLayerWatch(link.topics_of_type)
    watch.want(GLOBAL, True)
    try:
        assert wait_until(lambda: bool(watch.follow(link.ros) or watch.patches[GLOBAL] >= 2), 20, 0.1)
        whole = watch.costmap(GLOBAL)
        assert whole is not None and watch.errors == 0 and watch.counts[GLOBAL] == 1  # the patches changed nothing
        assert sim.mark_obstacle(3.0, 2.5, 0.2) > 30
        expected = sim.engine.layers.costs

        def arrived() -> bool:
            got = watch.costmap(GLOBAL)
            return got is not None and np.array_equal(got.data, expected)

        assert wait_until(arrived, 15, 0.1)
        patched = watch.costmap(GLOBAL)
        assert patched is not None and patched.data[50, 60] == LETHAL and whole.data[50, 60] != LETHAL
        assert patched.version == whole.version + 1 and watch.errors == 0
    finally:
        watch.stop()
