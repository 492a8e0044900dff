"""Issue 38: a ``/cmd_vel`` from elsewhere does not cancel a running navigation goal, as on a real chair.

Nav2's controller_server and move_base keep publishing their own velocity while a goal runs, so one
zero (or a burst of them) from another client is overwritten at the controller's next cycle and the
chair drives on. The simulator used to cancel the goal on any ``/cmd_vel``, which hid that a Stop
sending only zero velocity left a goal running. Only a cancel ends it: Nav2's ``cancel_goal``
service with a zero id (all goals) or move_base's empty GoalID on ``/move_base/cancel``, from any
client, in each bridge mode.
"""

from __future__ import annotations

import json
import math
import time

import pytest
import roslibpy
import websockets.sync.client as ws_client
from roslibpy.ros1 import actionlib

from pmk_nb.sim.cancel_service import ERROR_NONE
from tests.fixtures_sim import wait_until

START = (1.0, 6.0, 0.0)  # the demo floor's corridor
FAR = (14.0, 6.0)
ZERO = {"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}
MODES = [("ros2", "official"), ("ros2", "rs"), ("ros1", "official")]


def _pose(x: float, y: float, ros: str) -> dict:
    stamp = {"secs": 0, "nsecs": 0} if ros == "ros1" else {"sec": 0, "nanosec": 0}
    header = {"frame_id": "map", "stamp": stamp}
    return {"header": header, "pose": {"position": {"x": x, "y": y, "z": 0.0}, "orientation": {"w": 1.0}}}


def _start_goal(sim, ros_factory, ros: str) -> list:
    """A goal to FAR on its own connection (as another page's dashboard would send it); its results."""
    client_ros = ros_factory(sim)
    results: list = []
    if ros == "ros2":
        client = roslibpy.ActionClient(client_ros, "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
        goal = roslibpy.Goal({"pose": _pose(*FAR, ros), "behavior_tree": ""})
        client.send_goal(goal, results.append, None, results.append)
    else:
        client = actionlib.ActionClient(client_ros, "/move_base", "move_base_msgs/MoveBaseAction")
        sent = actionlib.Goal(client, roslibpy.Message({"target_pose": _pose(*FAR, ros)}))
        sent.on("result", results.append)
        sent.send()
    assert wait_until(lambda: sim.velocity[0] > 0.2, 10.0), "the goal never got the chair moving"
    return results


def _zero_burst(ws, ros: str, seconds: float = 1.0) -> None:
    kind = "geometry_msgs/msg/Twist" if ros == "ros2" else "geometry_msgs/Twist"
    ws.send(json.dumps({"op": "advertise", "topic": "/cmd_vel", "type": kind}))
    for _ in range(round(20 * seconds)):
        ws.send(json.dumps({"op": "publish", "topic": "/cmd_vel", "msg": ZERO}))
        time.sleep(0.05)


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "bridge"), MODES)
def test_zero_velocity_from_elsewhere_does_not_stop_a_goal(sim_factory, ros_factory, ros: str, bridge: str) -> None:
    sim = sim_factory(ros=ros, start_pose=START, bridge=bridge)
    _start_goal(sim, ros_factory, ros)
    x0 = sim.pose[0]
    with ws_client.connect(f"ws://127.0.0.1:{sim.port}") as ws:
        _zero_burst(ws, ros)
    assert sim.goal_status == "active", sim.goal_status
    assert sim.pose[0] - x0 > 0.3, "the controller's own velocity should have kept the chair going"
    assert wait_until(lambda: sim.velocity[0] > 0.1, 1.0)


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "bridge"), MODES)
def test_a_cancel_all_from_another_client_stops_the_goal(sim_factory, ros_factory, ros: str, bridge: str) -> None:
    sim = sim_factory(ros=ros, start_pose=START, bridge=bridge)
    results = _start_goal(sim, ros_factory, ros)
    with ws_client.connect(f"ws://127.0.0.1:{sim.port}") as ws:
        if ros == "ros2":  # action_msgs/srv/CancelGoal, zero id and stamp: every goal of the action
            ws.send(json.dumps({"op": "call_service", "id": "c", "service": "/navigate_to_pose/_action/cancel_goal"}))
            answer = json.loads(ws.recv(3))
            assert answer["op"] == "service_response" and answer["result"] is True, answer
            assert answer["values"]["return_code"] == ERROR_NONE and len(answer["values"]["goals_canceling"]) == 1
        else:  # actionlib: an empty GoalID cancels every goal
            ws.send(json.dumps({"op": "advertise", "topic": "/move_base/cancel", "type": "actionlib_msgs/GoalID"}))
            ws.send(json.dumps({"op": "publish", "topic": "/move_base/cancel", "msg": {"id": ""}}))
        assert wait_until(lambda: sim.velocity == (0.0, 0.0), 2.0)
    x = sim.pose[0]
    assert wait_until(lambda: False, 0.5) is False and math.isclose(sim.pose[0], x, abs_tol=0.02)
    assert sim.goal_status == "cancelled"
    assert wait_until(lambda: bool(results), 3.0), "the goal's own client was told"
