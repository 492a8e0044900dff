"""The Home screen: the map filling the page, its tool bar, the status line and what it says,
the preview's chair link and the chair's own ``/map``.
"""
