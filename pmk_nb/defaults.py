"""The converter's and the accessibility check's defaults, each declared once (issue 25).

The command line (``pmk convert``, ``pmk maps convert``, ``pmk check``), the maps folder, the Maps
screen, the rasteriser, the openings plan, the accessibility check and the simulator all read these
names, so a default changed here changes everywhere. Plain numbers only: a leaf every package may import.
"""

from __future__ import annotations

#: metres per cell when a command is not told
DEFAULT_RESOLUTION = 0.05
#: metres: the wall band drawn along the outline of every cell
DEFAULT_WALL_THICKNESS = 0.10
#: metres: a gap between cells up to this wide is a wall left out of the file (a door or transition opens it)
DEFAULT_MAX_WALL_GAP = 0.5
#: metres: the width of an opening made where the file gives no door geometry
DEFAULT_DOOR_WIDTH = 0.9
#: metres: the wheelchair's width, for the accessibility check (a chair profile may say otherwise)
DEFAULT_CHAIR_WIDTH = 0.70
#: cells: the largest grid written without being asked (~400 MB of int8)
DEFAULT_MAX_CELLS = 400_000_000
#: cells: the longest side Nav2's map_server loads (an int16 index); larger grids only when asked
NAV2_MAX_CELLS_PER_SIDE = 32767
