"""Navigation goals: one handle over every route (Nav2 action, move_base actionlib, goal topic), the goal
watch, the heartbeat, the Stop for goals, the words a person reads, and the initial pose.
"""
