"""What the chair sends, kept as the latest message: the stream hub, the typed records, throttling,
the map, tf, the navigation layers, the planned path, plotted fields and the topic inspector.
"""
