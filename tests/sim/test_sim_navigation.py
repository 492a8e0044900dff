"""The simulator's navigation servers seen by real clients: roslibpy's ROS 2 ActionClient over the
rosbridge action ops (NavigateToPose, NavigateThroughPoses) and roslibpy's ROS 1 actionlib client
(move_base), plus the ops' error cases."""

from __future__ import annotations

import json
import math
import threading
import time

import pytest
import roslibpy
from roslibpy.core import GoalStatus as Ros2Status
from roslibpy.ros1 import actionlib

from pmk_nb.sim.bridge_modes import BRIDGE_MODES
from tests.fixtures_sim import wait_until

START = (1.0, 6.0, 0.0)


def _pose(x: float, y: float, stamp: dict[str, int] | None = None) -> dict:
    header = {"frame_id": "map", "stamp": stamp or {"sec": 0, "nanosec": 0}}
    return {"header": header, "pose": {"position": {"x": x, "y": y, "z": 0.0}, "orientation": {"w": 1.0}}}


@pytest.mark.slow
def test_navigate_to_pose_feedback_and_result(sim_factory, ros_factory) -> None:
    sim = sim_factory(ros="ros2", start_pose=START)
    ros = ros_factory(sim)
    servers = roslibpy.Service(ros, "/rosapi/action_servers", "rosapi_msgs/srv/GetActionServers")
    assert set(servers.call(roslibpy.ServiceRequest({}), timeout=3)["action_servers"]) == {
        "/navigate_to_pose",
        "/navigate_through_poses",
    }
    client = roslibpy.ActionClient(ros, "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
    feedback, results, errors = [], [], []
    stamps: list[float] = []
    statuses: list[dict] = []
    roslibpy.Topic(ros, "/navigate_to_pose/_action/status", "action_msgs/msg/GoalStatusArray").subscribe(
        statuses.append
    )

    def on_feedback(fb):
        stamps.append(time.monotonic())
        feedback.append(fb)

    goal_id = client.send_goal(
        roslibpy.Goal({"pose": _pose(6.0, 6.0), "behavior_tree": ""}), results.append, on_feedback, errors.append
    )
    client.wait_goal(goal_id, 30)
    assert not errors and results[-1]["status"] is Ros2Status.SUCCEEDED
    assert results[-1]["values"]["error_code"] == 0
    left = [fb["distance_remaining"] for fb in feedback]
    assert left[0] > 4.5 and left[-1] < 0.5 and len(left) > 10
    rate = (len(stamps) - 1) / (stamps[-1] - stamps[0])
    assert 3.0 < rate < 8.0, f"feedback at {rate:.1f} Hz"
    assert {"current_pose", "navigation_time", "estimated_time_remaining"} <= set(feedback[-1])
    # the action's status topic: executing, then succeeded, for one goal id
    assert wait_until(lambda: statuses and statuses[-1]["status_list"][-1]["status"] == 4, 2.0)
    uuids = {tuple(e["goal_info"]["goal_id"]["uuid"]) for m in statuses for e in m["status_list"]}
    assert len(uuids) == 1 and len(next(iter(uuids))) == 16
    assert [m["status_list"][-1]["status"] for m in statuses][:1] == [2]


@pytest.mark.slow
@pytest.mark.parametrize("bridge", BRIDGE_MODES)
def test_cancel_is_handled_at_once_or_after_the_goal(sim_factory, ros_factory, bridge: str) -> None:
    """rs cancels at once; rosbridge_suite (goals not in new threads) handles the cancel only after
    the goal ended, so the chair arrives (issue 24, fact 3)."""
    sim = sim_factory(ros="ros2", start_pose=START, bridge=bridge)
    ros = ros_factory(sim)
    client = roslibpy.ActionClient(ros, "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
    results: list = []
    goal_id = client.send_goal(roslibpy.Goal({"pose": _pose(4.0, 6.0)}), results.append, None, results.append)
    assert wait_until(lambda: sim.velocity[0] > 0.2, 10.0)
    client.cancel_goal(goal_id)
    client.wait_goal(goal_id, 10)
    if bridge == "rs":  # canceled, with result: false (measured on rosbridge-server-rs 0.1.6)
        assert results[-1]["status"] is Ros2Status.CANCELED
        assert wait_until(lambda: sim.velocity == (0.0, 0.0), 0.5)
    else:
        assert results[-1]["status"] is Ros2Status.SUCCEEDED
        assert math.dist(sim.pose[:2], (4.0, 6.0)) < 0.2


@pytest.mark.slow
def test_through_poses_and_aborts_and_rejects(sim_factory, ros_factory) -> None:
    sim = sim_factory(ros="ros2", start_pose=START, bridge="rs")  # rs answers a rejected goal
    ros = ros_factory(sim)
    through = roslibpy.ActionClient(ros, "/navigate_through_poses", "nav2_msgs/action/NavigateThroughPoses")
    results, errors, ys = [], [], []
    gid = through.send_goal(
        roslibpy.Goal({"poses": [_pose(3.0, 9.0), _pose(8.0, 6.0)]}),
        results.append,
        lambda fb: ys.append(sim.pose[1]),
        errors.append,
    )
    through.wait_goal(gid, 60)
    assert results[-1]["status"] is Ros2Status.SUCCEEDED and max(ys) > 8.0
    assert math.dist(sim.pose[:2], (8.0, 6.0)) < 0.2
    to_pose = roslibpy.ActionClient(ros, "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
    gid = to_pose.send_goal(roslibpy.Goal({"pose": _pose(2.5, 1.5)}), results.append, None, errors.append)
    to_pose.wait_goal(gid, 15)  # inside the table: accepted, no path, aborted
    assert results[-1]["status"] is Ros2Status.ABORTED and "no path" in results[-1]["values"]["error_msg"]
    gid = to_pose.send_goal(roslibpy.Goal({"pose": _pose(90.0, 1.5)}), results.append, None, errors.append)
    to_pose.wait_goal(gid, 5)  # rs: status 6, result false, no reason (measured on 0.1.6)
    assert errors and errors[-1]["values"] == "goal rejected" and errors[-1]["status"] is Ros2Status.ABORTED
    assert any("outside the map" in note for note in sim.notes)


@pytest.mark.slow
def test_move_base_actionlib_goal_cancel_and_status(sim_factory, ros_factory) -> None:
    """ROS 1: rosbridge 0.11 has no action ops (issue 24, fact 4); move_base is actionlib topics."""
    sim = sim_factory(ros="ros1", start_pose=START)
    import websockets.sync.client as ws_client

    with ws_client.connect(f"ws://127.0.0.1:{sim.port}") as ws:
        ws.send(json.dumps({"op": "send_action_goal", "id": "g", "action": "/move_base", "args": {}}))
        answer = json.loads(ws.recv(3))
        assert answer["op"] == "status" and "Unknown operation 'send_action_goal'" in answer["msg"]
    ros = ros_factory(sim)
    client = actionlib.ActionClient(ros, "/move_base", "move_base_msgs/MoveBaseAction")  # waits for /status
    target = {"target_pose": _pose(6.0, 6.0, {"secs": 0, "nsecs": 0})}
    goal = actionlib.Goal(client, roslibpy.Message(target))
    feedback: list[dict] = []
    goal.on("feedback", feedback.append)
    goal.send()
    goal.wait(30)
    assert goal.status["status"] == actionlib.GoalStatus.SUCCEEDED
    assert feedback and "base_position" in feedback[-1]
    assert math.dist(sim.pose[:2], (6.0, 6.0)) < 0.2
    goal = actionlib.Goal(client, roslibpy.Message({"target_pose": _pose(15.0, 6.0, {"secs": 0, "nsecs": 0})}))
    goal.send()
    assert wait_until(lambda: sim.velocity[0] > 0.2, 10.0)
    goal.cancel()
    assert wait_until(lambda: (goal.status or {}).get("status") == actionlib.GoalStatus.PREEMPTED, 3.0)
    assert wait_until(lambda: sim.velocity == (0.0, 0.0), 0.5)


@pytest.mark.slow
@pytest.mark.parametrize("bridge", BRIDGE_MODES)
def test_a_rejected_goal_is_answered_or_never(sim_factory, ros_factory, bridge: str) -> None:
    """rs answers ``result: false``; rosbridge_suite never answers, and the client's later ops wait
    behind the goal for ever (its IncomingQueue is stuck): only a new connection works (fact 2)."""
    sim = sim_factory(ros="ros2", start_pose=START, bridge=bridge)
    ros = ros_factory(sim)
    got: list[dict] = []
    done = threading.Event()
    client = roslibpy.ActionClient(ros, "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
    client.send_goal(roslibpy.Goal({"pose": _pose(90.0, 1.5)}), got.append, None, lambda e: (got.append(e), done.set()))
    get_time = roslibpy.Service(ros, "/rosapi/get_time", "rosapi_msgs/srv/GetTime")
    if bridge == "rs":
        assert done.wait(3) and got[-1]["values"] == "goal rejected"
        assert get_time.call(roslibpy.ServiceRequest({}), timeout=2)["time"]["sec"] > 0
        return
    assert not done.wait(1.5) and not got
    with pytest.raises(Exception, match="No service response"):  # held: roslibpy gives up
        get_time.call(roslibpy.ServiceRequest({}), timeout=1)
    other = roslibpy.Service(ros_factory(sim), "/rosapi/get_time", "rosapi_msgs/srv/GetTime")
    assert other.call(roslibpy.ServiceRequest({}), timeout=2)["time"]["sec"] > 0


@pytest.mark.slow
@pytest.mark.parametrize("bridge", BRIDGE_MODES)
def test_action_op_errors_and_a_gone_client(sim_factory, ros_factory, bridge: str) -> None:
    """A client sends a goal and drops: rs cancels the gone client's goal; rosbridge_suite lets it
    run on to the end (fact 1)."""
    sim = sim_factory(ros="ros2", start_pose=START, bridge=bridge)
    if bridge == "rs":
        got: list[dict] = []
        done = threading.Event()
        client = roslibpy.ActionClient(ros_factory(sim), "/nope", "nav2_msgs/action/NavigateToPose")
        client.send_goal(roslibpy.Goal({}), got.append, None, lambda e: (got.append(e), done.set()))
        assert done.wait(3) and got[-1]["values"] == "Action /nope does not exist"
    import websockets.sync.client as ws_client

    target = 15.0 if bridge == "rs" else 4.0
    with ws_client.connect(f"ws://127.0.0.1:{sim.port}") as ws:
        ws.send(
            json.dumps(
                {
                    "op": "send_action_goal",
                    "id": "g1",
                    "action": "/navigate_to_pose",
                    "args": {"pose": _pose(target, 6.0)},
                }
            )
        )
        ws.send(json.dumps({"op": "cancel_action_goal", "action": "/navigate_to_pose"}))  # no id: refused
        assert json.loads(ws.recv(3))["op"] in ("action_feedback", "status")
        assert wait_until(lambda: sim.velocity[0] > 0.2, 10.0)
    if bridge == "rs":
        assert wait_until(lambda: sim.velocity == (0.0, 0.0), 1.0)
        assert sim.goal_status == "cancelled"
    else:
        assert not wait_until(lambda: sim.velocity == (0.0, 0.0), 0.5)  # the goal runs on ...
        assert wait_until(lambda: sim.goal_status == "reached", 10.0)  # ... to the end
        assert math.dist(sim.pose[:2], (target, 6.0)) < 0.2


@pytest.mark.slow
def test_patrol_waits_after_a_cancelled_goal(sim_factory, ros_factory) -> None:
    sim = sim_factory(ros="ros2", start_pose=START, patrol=True, bridge="rs")  # rs: the cancel acts at once
    ros = ros_factory(sim)
    client = roslibpy.ActionClient(ros, "/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
    results: list = []
    gid = client.send_goal(roslibpy.Goal({"pose": _pose(15.0, 6.0)}), results.append, None, results.append)
    assert wait_until(lambda: sim.velocity[0] > 0.2, 10.0)
    client.cancel_goal(gid)
    client.wait_goal(gid, 3)
    x, y, _ = sim.pose
    time.sleep(3.0)  # patrol resumes 5 s after a goal ends, as after a manual command
    assert math.dist(sim.pose[:2], (x, y)) < 0.02
    assert wait_until(lambda: math.dist(sim.pose[:2], (x, y)) > 0.2, 8.0), "patrol should resume later"
