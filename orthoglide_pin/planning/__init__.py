"""Part programs: G-code to a time-optimal plan under the machine's real limits.

* :mod:`~orthoglide_pin.planning.gcode`: a program read by the
  :mod:`orthoglide_pin.program` layer, its moves as blocks in the world frame;
* :mod:`~orthoglide_pin.planning.geometry`: lines, arcs and helices, exact and
  parametrised by arc length;
* :mod:`~orthoglide_pin.planning.quintic`: quintic Bezier curves by arc length;
* :mod:`~orthoglide_pin.planning.blend`: G2 corner blends (quintics matching
  point, tangent and curvature) within the ``G64`` tolerance;
* :mod:`~orthoglide_pin.planning.path`: sections from rest to rest, blended
  corners, containment in the cube and the slider limits;
* :mod:`~orthoglide_pin.planning.limits`: the limits and their constraints
  along the path (slider speed and acceleration, motor torque and speed, feed);
* :mod:`~orthoglide_pin.planning.parametrize`: the time-optimal path
  parametrisation (TOPP-RA, ``pip install 'orthoglide-pin[plan]'``), its
  stages solved in closed form by :mod:`~orthoglide_pin.planning.reachability`;
* :mod:`~orthoglide_pin.planning.verify`: the plan re-evaluated on a finer grid
  with the closed-loop dynamics;
* :mod:`~orthoglide_pin.planning.grid`: the planning grid refined where the
  speed must change fast (rests, feed steps, curvature changes, blends);
* :mod:`~orthoglide_pin.planning.tighten`: the limits tightened around a
  verification's overshoot only, and the slower fallback when that does not settle;
* :mod:`~orthoglide_pin.planning.jerk`: the slider jerk limit, by a
  jerk-limited re-timing of the second-order plan;
* :mod:`~orthoglide_pin.planning.jerk_kinematics`: the slider jerk along the
  path from its path derivatives;
* :mod:`~orthoglide_pin.planning.jerk_stops`: the stops of a jerk-limited plan
  where the curvature steps and at the ends of tight blends;
* :mod:`~orthoglide_pin.planning.batch`: a plan's sections evaluated in one
  batch (path forms, planning grids, verification);
* :mod:`~orthoglide_pin.planning.controller`: what a controller adds (feed and
  rapid overrides, the default path-control mode) and the stops of a plan;
* :mod:`~orthoglide_pin.planning.plan`: the whole plan of a program;
* :mod:`~orthoglide_pin.planning.plan_inputs`: its arguments checked, and the
  program refused before any grid is made;
* :mod:`~orthoglide_pin.planning.windows`: long sections planned in windows;
* :mod:`~orthoglide_pin.planning.assemble`: the sections put together (block
  times, worst uses, binding times) and the progress counted;
* :mod:`~orthoglide_pin.planning.sampling`: the plan sampled in time (``trajectory.csv``);
* :mod:`~orthoglide_pin.planning.trajectory_file`: the sampled plan written a
  chunk at a time (CSV or Parquet) and the light copy its page plots;
* :mod:`~orthoglide_pin.planning.shipped`: the example programs shipped.

The modules that import Pinocchio or toppra are loaded on first use of their names.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports
from orthoglide_pin.planning.gcode import Block, Program, read_program, read_program_file
from orthoglide_pin.planning.geometry import Piece
from orthoglide_pin.planning.path import Path, Section, build_path
from orthoglide_pin.planning.shipped import (
    EXAMPLE_PROGRAMS,
    example_program_file,
    example_program_text,
)

if TYPE_CHECKING:
    from orthoglide_pin.planning.controller import stop_reasons
    from orthoglide_pin.planning.limits import PlanLimits
    from orthoglide_pin.planning.plan import BlockTime, Plan, plan_program
    from orthoglide_pin.planning.tighten import Fallback

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "PlanLimits": "orthoglide_pin.planning.limits",
        "BlockTime": "orthoglide_pin.planning.plan",
        "Fallback": "orthoglide_pin.planning.tighten",
        "Plan": "orthoglide_pin.planning.plan",
        "plan_program": "orthoglide_pin.planning.plan",
        "stop_reasons": "orthoglide_pin.planning.controller",
    },
    globals(),
)

__all__ = [
    "EXAMPLE_PROGRAMS",
    "Block",
    "BlockTime",
    "Fallback",
    "Path",
    "Piece",
    "Plan",
    "PlanLimits",
    "Program",
    "Section",
    "build_path",
    "example_program_file",
    "example_program_text",
    "plan_program",
    "read_program",
    "read_program_file",
    "stop_reasons",
]
