"""The Orthoglide in a browser: a meshcat scene of the machine and its ellipsoids.

* :class:`Viewer`: the machine drawn from its URDF with its loops closed, the
  right way up (:mod:`~orthoglide_pin.viewer.orientation`: gravity down on
  screen, an axis triad, other mountings through ``up``), overlays (workspace
  cube, isotropic point, Q1/Q2, manipulability ellipsoids coloured by
  condition number on one scale with a legend, tool paths) and trajectory
  animations;
* :func:`read_trajectory`: a planned trajectory (``orthoglide plan``'s
  ``trajectory.csv``) read and checked, for :meth:`Viewer.play` (the path
  coloured by feed);
* :class:`Scene`: the scene recorded as meshcat commands, without a server;
* :func:`static_html`: one self-contained HTML file of a scene (offline);
* :class:`~orthoglide_pin.viewer.server.SceneServer`: a live server on
  127.0.0.1 only, started on demand.

Importing this package starts nothing: no server, no thread, no process.
"""

from __future__ import annotations

from orthoglide_pin.viewer.html import static_html
from orthoglide_pin.viewer.planned import PlannedTrajectory, read_trajectory
from orthoglide_pin.viewer.scene import Scene
from orthoglide_pin.viewer.visualizer import Viewer

__all__ = ["PlannedTrajectory", "Scene", "Viewer", "read_trajectory", "static_html"]
