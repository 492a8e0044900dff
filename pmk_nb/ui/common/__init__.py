"""The dashboard's shared layer: one session's state (``context``), the widgets and their safe
callbacks, the one style sheet (WCAG 2.2 AA parts included), the page's lifecycle and spoken feedback.
"""
