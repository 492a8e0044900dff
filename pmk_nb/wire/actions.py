"""The navigation stacks' actions as they appear on the wire: Nav2's actions (ROS 2 ``action_msgs``)
and move_base over actionlib (ROS 1), their names, types and goal status codes. The link sends goals
and reads these codes, the simulator serves them, the chair's goal watchdog cancels through them.
"""

from __future__ import annotations

# Nav2's actions and move_base's actionlib server: (name, type)
NAV2_ACTION = ("/navigate_to_pose", "nav2_msgs/action/NavigateToPose")
NAV2_THROUGH = ("/navigate_through_poses", "nav2_msgs/action/NavigateThroughPoses")
NAV2_ACTIONS = (NAV2_ACTION[0], NAV2_THROUGH[0])
MOVE_BASE = ("/move_base", "move_base_msgs/MoveBaseAction")
#: actionlib's cancel topic of move_base (an empty ``actionlib_msgs/GoalID`` cancels every goal)
MOVE_BASE_CANCEL = "/move_base/cancel"
#: an action's cancel service (``action_msgs/srv/CancelGoal``; a zero id and stamp cancels every goal)
CANCEL_GOAL_TYPE = "action_msgs/srv/CancelGoal"
#: an action's status topic type (``<action>/_action/status``)
GOAL_STATUS_ARRAY = "action_msgs/msg/GoalStatusArray"

# action_msgs/msg/GoalStatus (ROS 2 actions: Nav2)
STATUS_UNKNOWN = 0
STATUS_ACCEPTED = 1
STATUS_EXECUTING = 2
STATUS_CANCELING = 3
STATUS_SUCCEEDED = 4
STATUS_CANCELED = 5
STATUS_ABORTED = 6

# actionlib_msgs/GoalStatus (ROS 1 actionlib: move_base)
ACTIONLIB_PENDING = 0
ACTIONLIB_ACTIVE = 1
ACTIONLIB_PREEMPTED = 2
ACTIONLIB_SUCCEEDED = 3
ACTIONLIB_ABORTED = 4
ACTIONLIB_REJECTED = 5
ACTIONLIB_PREEMPTING = 6
ACTIONLIB_RECALLING = 7
ACTIONLIB_RECALLED = 8
ACTIONLIB_LOST = 9

# action_msgs/srv/CancelGoal return codes
CANCEL_ERROR_NONE = 0
CANCEL_ERROR_REJECTED = 1
CANCEL_ERROR_UNKNOWN_GOAL_ID = 2
CANCEL_ERROR_GOAL_TERMINATED = 3
