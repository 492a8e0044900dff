"""A stand-in for Nav2's bt_navigator in the real-stack tests: a real rclpy NavigateToPose action server.

Every goal is accepted and "drives" for ``--seconds`` (feedback at 10 Hz with the distance left),
then succeeds; a cancel request is accepted and ends the goal as canceled. Each event is one line on
stdout (``accepted``, ``cancel requested``, ``canceled``, ``succeeded``) with the time since the
goal was accepted, so that a test can read what the chair saw. Run with the wheels stack's python:
``python -m tests.ros2_nav_server [--seconds S]``; prints ``nav server: ready``.
"""

from __future__ import annotations

import argparse
import time
from typing import Any

READY_LINE = "nav server: ready"


def main() -> int:
    import rclpy
    from nav2_msgs.action import NavigateThroughPoses, NavigateToPose
    from rclpy.action import ActionServer, CancelResponse, GoalResponse
    from rclpy.callback_groups import ReentrantCallbackGroup
    from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor

    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=60.0)
    args = ap.parse_args()
    rclpy.init()
    node = rclpy.create_node("bt_navigator")
    group = ReentrantCallbackGroup()

    def execute(action: Any, name: str) -> Any:
        def run(handle: Any) -> Any:
            start = time.monotonic()
            print(f"{name} accepted", flush=True)
            while time.monotonic() - start < args.seconds:
                if handle.is_cancel_requested:
                    handle.canceled()
                    print(f"{name} canceled after {time.monotonic() - start:.2f} s", flush=True)
                    return action.Result(error_msg="canceled")
                feedback = action.Feedback()
                feedback.distance_remaining = float(args.seconds - (time.monotonic() - start))
                handle.publish_feedback(feedback)
                time.sleep(0.1)
            handle.succeed()
            print(f"{name} succeeded after {time.monotonic() - start:.2f} s", flush=True)
            return action.Result()

        return run

    def on_cancel(_request: Any) -> CancelResponse:
        print("cancel requested", flush=True)
        return CancelResponse.ACCEPT

    servers = [
        ActionServer(
            node,
            action,
            name,
            execute(action, name),
            goal_callback=lambda _goal: GoalResponse.ACCEPT,
            cancel_callback=on_cancel,
            callback_group=group,
        )
        for action, name in ((NavigateToPose, "/navigate_to_pose"), (NavigateThroughPoses, "/navigate_through_poses"))
    ]
    executor = MultiThreadedExecutor(num_threads=4)
    executor.add_node(node)
    print(READY_LINE, flush=True)
    try:
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        del servers
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
