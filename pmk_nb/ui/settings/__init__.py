"""The Settings screen: how to reach the chair (a profile), a connection test, the chair's keys."""
