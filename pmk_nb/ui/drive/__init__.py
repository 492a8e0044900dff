"""Home's Drive panel: the joystick, Stop and slow mode, and the page side of the stick."""
