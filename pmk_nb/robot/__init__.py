"""The chair side: ROS nodes a lab installs on its chair, and the wheels stack that runs them here.

- ``mapserver`` (+ ``mapstore``): the PMK map server (``pmk robot map-server``): ``/map`` (transient
  local), ``/map_metadata``, ``MapUpdate``, Nav2 ``LoadMap`` and a header-only ``MapInfo``.
- ``simnode``: the simulated chair's physics, laser and tf behind real rclpy topics (``pmk robot sim-node``).
- ``goalwatch`` + ``watchdog_ros2`` / ``watchdog_ros1``: the goal watchdog (``pmk robot goal-watchdog``),
  which cancels navigation goals when the dashboard's goal heartbeat falls silent.
- ``wheels``: a ROS 2 Jazzy stack from wheels (venv, interfaces built with cmake, rosbridge server).

rclpy/rospy are imported lazily, inside the nodes: the rest of the package never needs ROS.
"""
