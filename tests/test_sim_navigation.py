"""The simulator's navigation servers seen by real clients: roslibpy's ROS 2 ActionClient over the
rosbridge action ops (NavigateToPose, NavigateThroughPoses) and roslibpy's ROS 1 actionlib client
(move_base), plus the ops' error cases."""

from __future__ import annotations

import json
import math
import threading
import time

import roslibpy
from roslibpy.core import GoalStatus as Ros2Status
from roslibpy.ros1 import actionlib

from tests.fixtures_sim import wait_until

START = (1.0, 6.0, 0.0)


def _pose(x: float, y: float, stamp: dict[str, int] | None = None) -> dict:
    header = {"frame_id": "map", "stamp": stamp or {"sec": 0, "nanosec": 0}}
    return {"header": header, "pose": {"position": {"x": x, "y": y, "z": 0.0}, "orientation": {"w": 1.0}}}


def test_navigate_to_pose_feedback_result_and_cancel(sim_factory, ros_factory) -> None:
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
    # cancel a running goal: CANCELED and the chair stops
    goal_id = client.send_goal(roslibpy.Goal({"pose": _pose(15.0, 6.0)}), results.append, on_feedback, errors.append)
    assert wait_until(lambda: sim.velocity[0] > 0.2, 10.0)
    client.cancel_goal(goal_id)
    client.wait_goal(goal_id, 3)
    assert results[-1]["status"] is Ros2Status.CANCELED
    assert wait_until(lambda: sim.velocity == (0.0, 0.0), 0.5)


def test_through_poses_and_aborts_and_rejects(sim_factory, ros_factory) -> None:
    sim = sim_factory(ros="ros2", start_pose=START)
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
    to_pose.wait_goal(gid, 5)
    assert errors and "outside the map" in errors[-1]["values"]["error_msg"]


def test_move_base_actionlib_goal_cancel_and_status(sim_factory, ros_factory) -> None:
    sim = sim_factory(ros="ros1", start_pose=START)
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


def test_action_op_errors_and_a_gone_client(sim_factory, ros_factory) -> None:
    sim = sim_factory(ros="ros2", start_pose=START)
    ros = ros_factory(sim)
    got: list[dict] = []
    done = threading.Event()
    client = roslibpy.ActionClient(ros, "/nope", "nav2_msgs/action/NavigateToPose")
    client.send_goal(roslibpy.Goal({}), got.append, None, lambda e: (got.append(e), done.set()))
    assert done.wait(3) and got[-1]["values"] == "Action /nope does not exist"
    # a raw client sends a goal and drops: rosbridge cancels the goal of a gone client
    import websockets.sync.client as ws_client

    with ws_client.connect(f"ws://127.0.0.1:{sim.port}") as ws:
        ws.send(
            json.dumps(
                {
                    "op": "send_action_goal",
                    "id": "g1",
                    "action": "/navigate_to_pose",
                    "args": {"pose": _pose(15.0, 6.0)},
                }
            )
        )
        ws.send(json.dumps({"op": "cancel_action_goal", "action": "/navigate_to_pose"}))  # no id: refused
        assert json.loads(ws.recv(3))["op"] in ("action_feedback", "status")
        assert wait_until(lambda: sim.velocity[0] > 0.2, 10.0)
    assert wait_until(lambda: sim.velocity == (0.0, 0.0), 1.0)
    assert sim.goal_status == "cancelled"


def test_patrol_waits_after_a_cancelled_goal(sim_factory, ros_factory) -> None:
    sim = sim_factory(ros="ros2", start_pose=START, patrol=True)
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
