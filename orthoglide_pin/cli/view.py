"""Viewer command: ``view``, the machine and its ellipsoids in a browser (meshcat).

``orthoglide view`` draws the machine from its URDF with its loops closed, the
workspace cube, the isotropic point and Q1/Q2, optionally manipulability
ellipsoids (``--ellipsoids grid`` or ``--ellipsoids "x,y,z;x,y,z"``) and a
trajectory of the standard cycle played in the browser (``--trajectory NAME``),
or a planned one (``--trajectory DIR/trajectory.csv`` of ``orthoglide plan``,
or its ``.parquet`` form, the path coloured by feed), or the machine
oscillating in a natural mode at a point (``--mode N --at X Y Z``,
:mod:`orthoglide_pin.viewer.modes`).
The machine is drawn the right way up, with the axis triad of its frame (x
red, y green, z blue): ``--up`` names the machine axis that points up on
screen, ``-z`` by default (the prototype: gravity along ``+e3``, the vertical
slider above the platform); give a negative axis with ``=``: ``--up=-x``.
It then either serves the scene on ``http://127.0.0.1:PORT/`` until Ctrl-C, or
writes one self-contained HTML file (``--static FILE.html``) and exits.
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from orthoglide_pin.cli import _common as common
from orthoglide_pin.cli import _runtime as runtime
from orthoglide_pin.exceptions import InvalidParameterError, short_repr

if TYPE_CHECKING:
    from orthoglide_pin.machine.params import OrthoglideParams

#: Trajectories of ``--trajectory``: parts of the standard cycle
#: (:mod:`orthoglide_pin.motion.cycle`) by segment labels; ``None`` is the whole cycle.
TRAJECTORIES: Final[dict[str, tuple[str, ...] | None]] = {
    "cycle": None,
    "diagonal": ("diagonal Q1-Q2", "diagonal Q2-Q1"),
    "edges": tuple(
        f"edge {k} ({d})"
        for k, d in enumerate(("+x", "+y", "-x", "+z", "+x", "-y", "-x", "-z"), 1)
    ),
    "square": ("square 1", "square 2", "square 3", "square 4"),
    "circle": ("circle xy", "to circle yz", "circle yz", "to circle zx", "circle zx"),
    "circle-xy": ("circle xy",),
    "circle-yz": ("circle yz",),
    "circle-zx": ("circle zx",),
}
#: Values of ``--up`` and its default: :data:`~orthoglide_pin.viewer.orientation.UP_DIRECTIONS`,
#: repeated here so that the command line starts without importing the viewer.
UP_DIRECTIONS: Final = ("-z", "+z", "-x", "+x", "-y", "+y")
DEFAULT_UP: Final = "-z"
#: Default port of the live server.
DEFAULT_PORT: Final[int] = 7000


def named_trajectory(
    name: str, params: OrthoglideParams
) -> tuple[np.ndarray[Any, Any], np.ndarray[Any, Any]]:
    """Times [s], shape (N,), and tool points [m], shape (N, 3), of a named trajectory.

    The samples of the standard cycle from the first to the last segment of the
    name (the rests between them included).

    Raises:
        InvalidParameterError: If ``name`` is not one of :data:`TRAJECTORIES`.
    """
    from orthoglide_pin.motion.cycle import standard_cycle

    if name not in TRAJECTORIES:
        raise InvalidParameterError("--trajectory", name, "one of " + ", ".join(TRAJECTORIES))
    cycle = standard_cycle(params)
    labels = TRAJECTORIES[name]
    if labels is None:
        return cycle.t, cycle.p
    mask = np.zeros(len(cycle), dtype=bool)
    for label in labels:
        mask |= cycle.where(label)
    index = np.flatnonzero(mask)
    span = slice(int(index[0]), int(index[-1]) + 1)
    return cycle.t[span], cycle.p[span]


def parse_points(
    text: str, option: str = "--ellipsoids", allowed: str = '"grid" or points "x,y,z;x,y,z" [m]'
) -> np.ndarray[Any, Any]:
    """Points ``"x,y,z;x,y,z"`` [m] as an array of shape (N, 3).

    Args:
        text: The points.
        option: Name of the option, for the error message.
        allowed: What the option accepts, for the error message.

    Raises:
        InvalidParameterError: If a point is not three finite numbers.
    """
    rows = []
    for chunk in text.split(";"):
        if not chunk.strip():
            continue
        parts = chunk.split(",")
        try:
            row = [float(v) for v in parts]
        except ValueError:
            raise InvalidParameterError(option, text, allowed) from None
        if len(row) != 3 or not all(math.isfinite(v) for v in row):
            raise InvalidParameterError(option, text, allowed)
        rows.append(row)
    if not rows:
        raise InvalidParameterError(option, text, allowed)
    return np.array(rows)


def _cmd_view(args: argparse.Namespace) -> int:
    from orthoglide_pin.report.units import quantity
    from orthoglide_pin.viewer import Viewer

    params = common.build_params(args)
    trajectory = None if not args.trajectory else _trajectory(args.trajectory, params)
    viewer = Viewer(common.closed_loop_model(params), up=args.up)
    viewer.add_workspace()
    payload: dict[str, Any] = {"visuals": len(viewer.drawing), "ellipsoids": 0, "frames": 0}
    payload["cube"] = params.workspace.to_dict()
    payload["up"] = viewer.up
    lines = [
        f"Orthoglide: {len(viewer.drawing)} visuals from the URDF, "
        f"workspace {params.workspace.describe()}",
        f"  {viewer.up} up on screen; axes x red, y green, z blue",
    ]
    if args.point is not None:
        viewer.show_point(parse_points(args.point, "--point", "one point x,y,z [m]")[0])
    if args.ellipsoids:
        if args.ellipsoids.strip().lower() == "grid":
            points = viewer.grid_points(args.grid)
        else:
            points = parse_points(args.ellipsoids)
        ells = viewer.add_ellipsoids(points, args.ellipsoid_kind)
        payload["ellipsoids"] = len(ells.points)
        lines.append(
            f"  {len(ells.points)} {args.ellipsoid_kind} ellipsoids, condition number "
            f"{ells.condition.min():.3f} to {ells.condition.max():.3f}"
        )
    if args.mode is not None or args.at is not None:
        lines.extend(_play_mode(viewer, args, payload))
    if trajectory is not None:
        follow = None if args.no_follow else args.ellipsoid_kind
        frames = viewer.play(trajectory, follow=follow, time_scale=args.time_scale)
        payload["frames"] = len(frames.times)
        lines.append(
            f"  trajectory {args.trajectory}: {len(frames.times)} frames over "
            f"{frames.times[-1]:.2f} s at {frames.fps:.1f} frames/s"
        )
        speed = getattr(trajectory, "path_speed", None)
        if speed is not None:
            payload["max_path_speed"] = float(speed.max())
            top = quantity("feed", float(speed.max()), ".0f")
            lines.append(f"  path coloured by feed, 0 to {top}")
    if args.static:
        path = viewer.save_html(args.static).resolve()
        payload["static"] = str(path)
        lines.append(f"  wrote {path} ({path.stat().st_size / 1e3:.0f} kB, opens offline)")
        return common.emit(args, payload, "\n".join(lines))
    url = viewer.serve(args.port)
    payload["url"] = url
    lines.append(f"  serving on {url} (Ctrl-C to stop)")
    common.emit(args, payload, "\n".join(lines))
    sys.stdout.flush()
    try:  # until Ctrl-C (exit 130) or SIGTERM (exit 143), one line each
        runtime.wait_for_signal(lambda: viewer.url() is not None)
    finally:
        viewer.close()
    return 0


def _play_mode(viewer: Any, args: argparse.Namespace, payload: dict[str, Any]) -> list[str]:
    """``--mode N --at X Y Z``: animate the mode; the lines to print."""
    if args.mode is None or args.at is None:
        given, missing = ("--mode", "--at X Y Z") if args.at is None else ("--at", "--mode N")
        raise InvalidParameterError(given, "alone", f"{missing} with it")
    if args.trajectory:
        raise InvalidParameterError(
            "--mode", args.mode, "no --trajectory: one animation at a time"
        )
    from orthoglide_pin.drives.motor import load_drive

    point = common.numbers("--at", args.at, "X Y Z or X,Y,Z [m]", 3)
    drive = None if args.motor is None else load_drive(args.motor)
    amplitude = None if args.amplitude is None else float(args.amplitude)
    motion = viewer.play_mode(
        point, args.mode, drive=drive, vibration_model=args.model, amplitude=amplitude
    )
    payload["frames"] = len(motion.frames.times)
    payload["mode"] = {
        "number": motion.mode,
        "model": args.model,
        "point": motion.point.tolist(),
        "frequency": motion.frequency,
        "tool_direction": motion.direction.tolist(),
        "platform_rotation": motion.rotation.tolist(),
        "swing": motion.scale,
        "drive_mass": motion.modes.drive_mass,
    }
    energy = motion.modes.energy.reshape(-1, 3)[motion.mode - 1]
    return [
        f"  mode {motion.mode} at {common.fmt(point)} m ({args.model} model): "
        f"{motion.frequency:.2f} Hz, tool direction {common.fmt(motion.direction, 1.0, '+.3f')}",
        f"  drawn: tool swing {1e3 * motion.scale:.2f} mm, one period every "
        f"{motion.frames.times[-1]:g} s; legs rigid (members hold {100 * energy[2]:.0f} % "
        "of the mode's kinetic energy, not drawn)",
    ]


def _trajectory(value: str, params: OrthoglideParams) -> Any:
    """A part of the standard cycle, or a planned trajectory file (``.csv`` or ``.parquet``)."""
    if value in TRAJECTORIES:
        return named_trajectory(value, params)
    if not value.lower().endswith((".csv", ".parquet")):
        raise InvalidParameterError(
            "--trajectory",
            value,
            "one of " + ", ".join(TRAJECTORIES) + ", or a planned trajectory FILE.csv|.parquet",
        )
    from orthoglide_pin.viewer.planned import read_trajectory

    return read_trajectory(value, params)


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {short_repr(text)}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text}")
    return value


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer, got {short_repr(text)}") from None
    if not 2 <= value <= 20:
        raise argparse.ArgumentTypeError(f"must be in [2, 20], got {value}")
    return value


def _up(text: str) -> str:
    from orthoglide_pin.viewer.orientation import check_up

    try:
        return check_up(text)
    except InvalidParameterError:
        raise argparse.ArgumentTypeError(
            f"must be one of {', '.join(UP_DIRECTIONS)}, got {short_repr(text)}"
        ) from None


def _port(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer, got {short_repr(text)}") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"must be in [0, 65535], got {value}")
    return value


def register(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], parent: argparse.ArgumentParser
) -> None:
    """Add the ``view`` command."""
    p = common.add_command(
        sub,
        parent,
        "view",
        _cmd_view,
        "the machine, its workspace and ellipsoids in a browser: a live server on "
        "127.0.0.1 (Ctrl-C stops it) or one self-contained HTML file (--static)",
    )
    p.add_argument(
        "--ellipsoids",
        metavar="grid|POINTS",
        help='manipulability ellipsoids: "grid" (over the cube) or points "x,y,z;x,y,z" [m]',
    )
    p.add_argument("--grid", type=_count, default=3, metavar="N", help="grid points per edge")
    p.add_argument(
        "--ellipsoid-kind",
        choices=("velocity", "force", "compliance"),
        default="velocity",
        help="velocity (semi-axes: transmission factors), force, or compliance ellipsoids "
        "(tool displacement per unit force [um/N], the elastostatic model; default velocity)",
    )
    p.add_argument(
        "--trajectory",
        metavar="NAME|FILE.csv",
        help="play a part of the standard cycle ("
        + ", ".join(TRAJECTORIES)
        + "), or a planned trajectory of this design (orthoglide plan's DIR/trajectory.csv "
        "or simulate's DIR/simulation.csv, or their .parquet form, the path coloured by feed)",
    )
    p.add_argument(
        "--time-scale",
        type=_positive,
        default=1.0,
        metavar="S",
        help="animation time over trajectory time (2: half speed; default 1)",
    )
    p.add_argument(
        "--no-follow", action="store_true", help="no ellipsoid following the tool along the path"
    )
    p.add_argument("--point", metavar="X,Y,Z", help="tool point to show [m] (default: home)")
    p.add_argument(
        "--mode",
        type=int,
        metavar="N",
        help="animate natural mode N (1: the lowest) at the point --at: the platform swings "
        "along the mode's shape, the legs follow it, one period every 2 s",
    )
    p.add_argument("--at", nargs="+", metavar=("X", "Y", "Z"), help="tool point of --mode [m]")
    p.add_argument(
        "--model",
        choices=("platform", "full"),
        default="platform",
        help="vibration model of --mode (default platform: the six platform modes; full: "
        "with the members' own modes, whose bending is not drawn)",
    )
    p.add_argument(
        "--motor",
        metavar="FILE.yaml",
        help="drive file of --mode: its rotary inertia is reflected onto each carriage "
        "(without it the carriages move alone)",
    )
    p.add_argument(
        "--amplitude",
        type=_positive,
        metavar="A",
        help="largest displacement drawn of the tool tip and the platform's joints in --mode "
        "[m] (default: 5 %% of the cube's side; the real amplitude of a mode is arbitrary)",
    )
    p.add_argument(
        "--up",
        type=_up,
        default=DEFAULT_UP,
        metavar="AXIS",
        help="machine axis pointing up on screen: "
        + ", ".join(UP_DIRECTIONS)
        + f" (default {DEFAULT_UP}: the prototype, gravity along +z; write --up=-x)",
    )
    p.add_argument(
        "--port", type=_port, default=DEFAULT_PORT, help="port of the live server (0: any free)"
    )
    p.add_argument(
        "--static", metavar="FILE.html", help="write one self-contained HTML file and exit"
    )
