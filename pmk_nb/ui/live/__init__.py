"""The live view: the ipycanvas map, chair and laser layers, gestures, map tools, the frame clock and
the canvas fixes. It only draws what ``pmk_nb.viewport`` computes.
"""
