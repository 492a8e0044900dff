"""What the link asks the chair: rosapi discovery, the map reload services, the published map's facts,
which rosbridge it runs, and the connection test.
"""
