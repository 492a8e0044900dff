"""PMK Notebook: building plans to ROS maps, map deployment and live preview for the PMK wheelchair."""

from __future__ import annotations

__version__ = "0.1.0"
