"""Recording the chair's topics to MCAP with ROS 2 schemas: the recorder, the JSON -> ROS 2 conversion
and the message definitions (bundled or described by the bridge).
"""
