"""The planned path (issue 29, item 4): the simulator publishes nav_msgs/Path where Nav2 (/plan) and
move_base (/move_base/NavfnROS/plan) do, and the link's PlanWatch follows it through real roslibpy."""

from __future__ import annotations

import math
import time
from typing import Any

import pytest

from pmk_nb.chair.link.query.discovery import RosapiMissing
from pmk_nb.chair.link.streams.planpath import PLAN_TOPICS, PlanWatch, parse_path
from tests.fixtures_sim import wait_until


def test_parse_path_keeps_finite_points_and_the_frame() -> None:
    msg = {
        "header": {"frame_id": "/map"},
        "poses": [
            {"pose": {"position": {"x": 1, "y": 2.5}}},
            {"pose": {"position": {"x": None, "y": 1.0}}},  # NaN on the wire: dropped
            "garbage",
            {"pose": {"position": {"x": 3.0, "y": 4.0}}},
        ],
    }
    path = parse_path(msg, "/plan", 1.0)
    assert path.points.tolist() == [[1.0, 2.5], [3.0, 4.0]] and path.frame == "map" and path.topic == "/plan"
    assert parse_path({}, "/plan", 0.0).points.shape == (0, 2)


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "topic"), [("ros2", "/plan"), ("ros1", "/move_base/NavfnROS/plan")])
def test_the_simulator_publishes_its_plan_and_the_link_follows_it(
    sim_factory: Any, link_factory: Any, ros: str, topic: str
) -> None:
    sim = sim_factory(ros=ros, start_pose=(1.0, 6.0, 0.0), patrol=False)
    link = link_factory(sim)
    watch = PlanWatch(lookup=link.discovery.topics, relook_s=0.2)  # "auto": the plan topics the chair lists
    # looked up before the goal: a ROS 2 bridge answers no call on the goal's connection while it runs
    assert wait_until(lambda: watch.follow(link.ros) or watch.subscribed, 15.0), "no plan topic listed"
    handle = link.navigate_to(12.0, 6.0, 0.0)
    assert wait_until(lambda: watch.latest is not None, 15.0), "no nav_msgs/Path from the simulator"
    path = watch.latest
    assert path is not None and path.topic == topic and path.frame == "map"
    assert path.points.shape[0] >= 2
    assert math.dist(path.points[0], (1.0, 6.0)) < 0.5 and math.dist(path.points[-1], (12.0, 6.0)) < 0.2
    first = watch.count
    assert wait_until(lambda: watch.count > first, 5.0), "the plan is published again while it is driven"
    handle.cancel()
    watch.stop()
    assert watch.latest is None
    named = PlanWatch(topic)
    assert named.topics == (topic,)


@pytest.mark.slow
def test_the_plan_subscription_comes_back_after_the_chair_restarts(sim_factory: Any) -> None:
    """The link's Ros reconnects by itself; the plan's own subscription is sent again then."""
    from pmk_nb.chair.link.client import ChairLink
    from pmk_nb.chair.link.transport.state import LinkState

    sim = sim_factory(ros="ros2", start_pose=(1.0, 6.0, 0.0), patrol=False)
    link = ChairLink("127.0.0.1", sim.port, reconnect_initial=0.2, reconnect_max=1.0)
    try:
        link.connect(timeout=10.0)
        watch = PlanWatch("/plan")
        watch.follow(link.ros)
        link.navigate_to(12.0, 6.0, 0.0)
        assert wait_until(lambda: watch.latest is not None, 15.0)
        sim.stop()
        assert wait_until(lambda: link.state is LinkState.CONNECTING, 5.0)
        sim.start()
        assert wait_until(lambda: link.state is LinkState.CONNECTED, 10.0)
        watch.follow(link.ros)  # the same Ros: nothing new subscribed here
        time.sleep(2.0)  # the subscribe goes out 1 s after the close, as roslibpy's own topics do
        count = watch.count
        link.navigate_to(12.0, 3.0, 0.0)  # far: planned and published again while it drives
        assert wait_until(lambda: watch.count > count, 15.0), "no plan after the reconnect"
        watch.stop()
    finally:
        link.close()


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "theirs"), [("ros2", "/plan"), ("ros1", "/move_base/NavfnROS/plan")])
def test_auto_subscribes_only_the_plan_topics_the_chair_lists(
    sim_factory: Any, link_factory: Any, ros: str, theirs: str
) -> None:
    """Issue 40, item 6: on a ROS 2 chair the lookup made /move_base/GlobalPlanner/plan and
    /move_base/NavfnROS/plan appear (a subscription names its type, so the bridge creates the topic)."""
    sim = sim_factory(ros=ros, start_pose=(1.0, 6.0, 0.0), patrol=False)
    link = link_factory(sim)
    watch = PlanWatch(lookup=link.discovery.topics, relook_s=0.2)
    assert wait_until(lambda: watch.follow(link.ros) or watch.subscribed, 15.0), "no plan topic listed"
    assert watch.subscribed == (theirs,)
    handle = link.navigate_to(12.0, 6.0, 0.0)
    assert wait_until(lambda: watch.latest is not None, 15.0), "no plan followed"
    handle.cancel()
    assert handle.wait(15.0) is not None
    listed = set(link.discovery.topics(timeout=10.0))
    assert not {t for t in PLAN_TOPICS if t != theirs} & listed, f"guessed topics appeared: {sorted(listed)}"
    watch.stop()


def test_without_rosapi_auto_guesses_nothing() -> None:
    calls: list[float] = []

    def no_rosapi() -> list[str]:
        calls.append(time.monotonic())
        raise RosapiMissing("127.0.0.1:9090", "/rosapi/topics", "no such service")

    ros = object()
    watch = PlanWatch(lookup=no_rosapi, relook_s=0.0)
    # a second lookup starts only once the first has finished: then its answer has been taken
    assert wait_until(lambda: watch.follow(ros) or len(calls) >= 2, 5.0)  # type: ignore[arg-type]
    assert watch.subscribed == ()
