"""Kiosk mode: Home only with big targets on a tablet; the PIN that opens the other screens."""
