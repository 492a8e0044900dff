"""Alias: the spawner moved to :mod:`pmk_nb.serve.hub_spawner` (issue 42).

A class folder's ``jupyterhub_config.json`` written before the move names
``pmk_nb.cli.hub_spawner.ClassSpawner``; this keeps that file working until ``pmk hub`` writes it again.
"""

from pmk_nb.serve import ClassSpawner

__all__ = ["ClassSpawner"]
