"""The viewer: the machine, its overlays and animations in a browser (meshcat).

:class:`Viewer` draws a closed-loop model from its URDF's visuals
(:mod:`~orthoglide_pin.viewer.machine`), adds overlays
(:mod:`~orthoglide_pin.viewer.overlays`) and plays trajectories
(:mod:`~orthoglide_pin.viewer.animation`) and natural modes
(:mod:`~orthoglide_pin.viewer.modes`). Everything is recorded in a
:class:`~orthoglide_pin.viewer.scene.Scene` without any server, so a scene can
be built and exported to one self-contained HTML file headless
(:meth:`Viewer.save_html`), shown inline in a notebook (``_repr_html_``), or
served live on 127.0.0.1 (:meth:`Viewer.serve`), where later changes reach the
open pages at once.

Scene layout (meshcat paths): the machine under ``/meshcat/orthoglide/machine``,
overlays under ``/meshcat/orthoglide/{workspace,ellipsoids,path,follower,mode}`` and
the axis triad under ``/meshcat/orthoglide/axes``. The root node turns the
machine the right way up (``up``, see :mod:`~orthoglide_pin.viewer.orientation`:
by default ``-z`` is up, so gravity points down on screen and the vertical
slider sits above the platform, as on the prototype) and shifts the scene so
that the machine's centre sits at the viewer's origin, the point the camera
orbits; coordinates below it are the machine's world frame [m] (origin at the
tool tip at home).

Colours: every ellipsoid drawn (those of :meth:`Viewer.add_ellipsoids` and the
one that follows the tool in :meth:`Viewer.play`) takes its colour from one
:class:`~orthoglide_pin.viewer.overlays.ColorScale`, the one the legend's bar
shows: its range grows to cover every condition number drawn, unless the user
fixed it (then colours are clamped to its ends and the legend says so).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import (
    finite_rows,
    finite_vector,
    flag,
    positive_length,
    positive_number,
)
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.viewer import animation, modes, orientation, overlays, planned
from orthoglide_pin.viewer.machine import MachineDrawing
from orthoglide_pin.viewer.output import SceneOutput

if TYPE_CHECKING:
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: Root of everything the viewer draws.
ROOT: Final[str] = "/meshcat/orthoglide"
#: meshcat's default camera (its parent turns three.js's y-up into z-up).
CAMERA: Final[str] = "/Cameras/default/rotated/<object>"
#: Camera distance over the distance at which the machine's bounding sphere fills the view.
FRAMING: Final[float] = 0.9
#: Vertical field of view of meshcat's default camera [deg].
CAMERA_FOV: Final[float] = 75.0
#: Background gradient (RGB in [0, 1]): white to a light grey.
BACKGROUND: Final = ((1.0, 1.0, 1.0), (0.84, 0.86, 0.89))
#: Length of the axis triad drawn at the origin, over the workspace cube's side.
TRIAD_FRACTION: Final[float] = 0.5
#: Most points drawn for a tool path.
MAX_PATH_POINTS: Final[int] = 4000
#: Colour of a mode's tool swing (the segment it runs along).
MODE_RGB: Final = (0.85, 0.1, 0.1)


class Viewer(SceneOutput):
    """The Orthoglide in a browser: machine, overlays, animations (meshcat).

    Building a viewer starts no server: see :meth:`serve`.

    Args:
        model: The closed-loop model, or the parameters to build it from; the
            prototype's when ``None``.
        title: Title of the page.
        up: The machine axis drawn pointing up on screen: ``"-z"`` (the
            prototype's mounting, gravity along ``+e3``), ``"+z"``, ``"-x"``,
            ``"+x"``, ``"-y"`` or ``"+y"``
            (see :mod:`~orthoglide_pin.viewer.orientation`).

    Attributes:
        model: The closed-loop model.
        scene: The recorded scene.
        drawing: The machine's visuals.
        configuration: The configuration shown [m, rad], shape (18,).
        ellipsoids: The ellipsoids drawn by :meth:`add_ellipsoids`, or ``None``.
        follower: The ellipsoids along the animation of :meth:`play`, or ``None``.
        color_scale: The condition number's colour scale of every ellipsoid
            drawn and of the legend's bar, or ``None`` without ellipsoids.
        up: The machine axis pointing up on screen (canonical form).
    """

    def __init__(
        self,
        model: ClosedLoopModel | OrthoglideParams | None = None,
        *,
        title: str = "Orthoglide",
        up: str = orientation.DEFAULT_UP,
    ) -> None:
        from orthoglide_pin.machine.closed_loop import as_model

        up = orientation.check_up(up)
        model = as_model(model, "model")
        super().__init__(title)
        self.model = model
        self.drawing = MachineDrawing(model)
        self.configuration = model.neutral()
        self.up = up
        self.ellipsoids: overlays.Ellipsoids | None = None
        self.follower: overlays.Ellipsoids | None = None
        self.color_scale: overlays.ColorScale | None = None
        self._items: dict[str, Any] = {}
        self._colormap = overlays.COLORMAP
        self._range: tuple[float | None, float | None] = (None, None)
        self._animation: tuple[animation.AnimationBuilder, int] | None = None
        self._setup()

    def _setup(self) -> None:
        s = self.scene
        s.set_property("/Background", "top_color", list(BACKGROUND[0]))
        s.set_property("/Background", "bottom_color", list(BACKGROUND[1]))
        s.set_property("/Grid", "visible", False)
        s.set_property("/Axes", "visible", False)
        self.drawing.draw(s, ROOT, self.configuration)
        _, side = self.workspace_cube()
        for name, (obj, matrix) in orientation.triad(TRIAD_FRACTION * side).items():
            s.set_object(f"{ROOT}/axes/{name}", obj)
            s.set_transform(f"{ROOT}/axes/{name}", matrix)
        self._frame()
        self._legend()

    def _frame(self) -> None:
        """Turn the machine up, centre it and its cube on the viewer's origin, aim the camera."""
        lower, upper = self.drawing.bounds(self.model.neutral())
        corner, side = self.workspace_cube()
        lower, upper = np.minimum(lower, corner), np.maximum(upper, corner + side)
        centre, radius = 0.5 * (lower + upper), 0.5 * float(np.linalg.norm(upper - lower))
        self.scene.set_transform(ROOT, orientation.root_transform(self.up, centre))
        distance = FRAMING * radius / math.sin(math.radians(CAMERA_FOV / 2))
        d = orientation.up_rotation(self.up) @ orientation.view_direction(self.up)
        w = distance * d  # meshcat's frame; the camera's parent is Rx(pi/2): (x, z, -y)
        self.scene.set_property(CAMERA, "position", [float(w[0]), float(w[2]), float(-w[1])])

    def _legend(self) -> None:
        items = {**self._items, **orientation.legend_items(self.up)}
        bar, values = None, []
        if self.color_scale is not None:
            still, follower = self.ellipsoids, self.follower
            if still is not None and follower is not None:
                what = f"{still.kind} ellipsoids, and the {follower.kind} one following the tool"
            elif still is not None:
                what = f"{still.kind} ellipsoids"
            else:
                assert follower is not None
                what = f"{follower.kind} ellipsoid following the tool"
            title = f"condition number [-] of the {what}"
            if "compliance" in (e.kind for e in (still, follower) if e is not None):
                m = self.model.params
                title += (
                    f" (semi-axes in um/N; E = {m.youngs_modulus / 1e9:.3g} GPa, "
                    f"G = {m.shear_modulus / 1e9:.3g} GPa, drives "
                    f"{m.actuator_stiffness / 1e6:.3g} N/um, ideal revolutes)"
                )
            bar = (title, self.color_scale)
            values = [e.condition for e in (still, follower) if e is not None]
        drawn_values = np.concatenate(values) if values else None
        self.scene.set_legend(overlays.legend(items, bar, drawn_values))

    def _recolor(self) -> None:
        """Set the colour scale from every ellipsoid drawn and recolour them on it."""
        drawn = [e.condition for e in (self.ellipsoids, self.follower) if e is not None]
        if not drawn:
            self.color_scale = None
            self._legend()
            return
        vmin, vmax = self._range
        scale = overlays.ColorScale.covering(np.concatenate(drawn), self._colormap, vmin, vmax)
        self.color_scale = scale
        if self.ellipsoids is not None:
            for k, rgb in enumerate(scale.rgb(self.ellipsoids.condition)):
                self.scene.set_object(f"{ROOT}/ellipsoids/{k}", overlays.sphere(1.0, rgb))
        if self.follower is not None and self._animation is not None:
            builder, repetitions = self._animation
            rgb = scale.rgb(self.follower.condition)
            self.scene.set_object(f"{ROOT}/follower", overlays.sphere(1.0, rgb[0]))
            builder.colors(f"{ROOT}/follower/<object>", rgb)
            self.scene.set_animation(builder.animation, play=True, repetitions=repetitions)
        self._legend()

    # -------------------------------------------------------------- machine
    def show(self, configuration: ArrayLike) -> None:
        """Show a configuration of the 18 joints [m, rad] (its loops closed)."""
        q = finite_vector("configuration", configuration, self.model.nv, "[m, rad]")
        self.drawing.place(self.scene, ROOT, q)
        self.configuration = q.copy()

    def show_point(self, point: ArrayLike) -> FloatArray:
        """Show the machine with its tool at ``point`` [m]; return the configuration (18,)."""
        q = self.model.configuration(finite_vector("point", point, 3, "[m]"))
        self.show(q)
        return q

    def show_sliders(self, q_actuated: ArrayLike) -> FloatArray:
        """Show the machine for slider values [m], loops closed by Newton; return (18,)."""
        q = self.model.solve(q_actuated, self.configuration).q
        self.show(q)
        return q

    # ------------------------------------------------------------- overlays
    def workspace_cube(self) -> tuple[FloatArray, float]:
        """The machine's prescribed cube: lower corner Q1 [m], shape (3,), and side [m].

        The cube of the design's parameters
        (:attr:`~orthoglide_pin.machine.params.OrthoglideParams.workspace`).
        """
        cube = self.model.params.workspace
        return cube.q1, float(cube.side)

    def add_workspace(
        self, corner: ArrayLike | None = None, side: float | None = None, *, markers: bool = True
    ) -> None:
        """Draw the workspace cube (wireframe) and mark the isotropic point, Q1 and Q2.

        Args:
            corner: Lowest corner Q1 [m], shape (3,); by default that of the
                machine's prescribed cube (:meth:`workspace_cube`).
            side: Side [m] (Q2 = Q1 + side (1, 1, 1)); by default the cube's.
            markers: Also draw the three points.
        """
        default_corner, default_side = self.workspace_cube()
        c = default_corner if corner is None else finite_vector("corner", corner, 3, "[m]")
        h = default_side if side is None else positive_length("side", side)
        self.scene.set_object(f"{ROOT}/workspace/cube", overlays.cube_wireframe(c, h))
        self._items["workspace cube"] = overlays.CUBE_RGB
        if flag("markers", markers):
            where = {"isotropic point": np.zeros(3), "Q1": c, "Q2": c + h}
            for name, point in where.items():
                path = f"{ROOT}/workspace/{name.replace(' ', '_')}"
                rgb = overlays.MARKER_RGB[name]
                self.scene.set_object(path, overlays.sphere(overlays.MARKER_RADIUS, rgb))
                self.scene.set_transform(path, overlays.translation(point))
                self._items[name] = rgb
        self._legend()

    def grid_points(self, n: int = 3) -> FloatArray:
        """``n^3`` points spanning the workspace cube [m], shape (n^3, 3).

        Raises:
            InvalidParameterError: ``n`` not an integer in ``[2, MAX_GRID_EDGE]``
                (:data:`orthoglide_pin.viewer.overlays.MAX_GRID_EDGE`), checked
                before anything is allocated.
        """
        from orthoglide_pin.kinetostatics.workspace import cube_grid

        if isinstance(n, bool) or not isinstance(n, int) or not 2 <= n <= overlays.MAX_GRID_EDGE:
            raise InvalidParameterError("n", n, f"an integer in [2, {overlays.MAX_GRID_EDGE}]")
        corner, side = self.workspace_cube()
        return cube_grid(corner, side, n).points().reshape(-1, 3)

    def add_ellipsoids(
        self,
        points: ArrayLike,
        kind: str = "velocity",
        *,
        scale: float = overlays.ELLIPSOID_SCALE,
        colormap: str = overlays.COLORMAP,
        vmin: float | None = None,
        vmax: float | None = None,
    ) -> overlays.Ellipsoids:
        """Draw manipulability ellipsoids at tool points, coloured by condition number.

        Replaces the ellipsoids drawn before. Their colour scale (the legend's
        bar) is shared with the ellipsoid that follows the tool in :meth:`play`.

        Args:
            points: Tool points [m], shape (3,) or (N, 3).
            kind: ``"velocity"`` (semi-axes: transmission factors), ``"force"``
                or ``"compliance"`` (tool displacement per unit force [um/N]:
                the elastostatic model).
            scale: Drawing scale [m per unit semi-axis].
            colormap: matplotlib colormap of the condition number.
            vmin: Condition number at the colormap's start (default 1).
            vmax: Condition number at its end (default: the largest of every
                ellipsoid drawn, the follower's included). Given bounds fix
                the range: values beyond it get the colour of its end.

        Returns:
            The ellipsoids drawn.
        """
        scale = positive_number("scale", scale, "a positive number")
        overlays.colors([1.0], 0.0, 1.0, colormap)  # an unknown colormap fails here
        ells = overlays.ellipsoids(points, self.model.params.leg_length, kind, self.model.params)
        overlays.color_range(ells.condition, vmin, vmax)  # so does a non-finite range
        matrices = overlays.ellipsoid_matrix(ells.points, ells.axes, ells.directions, scale)
        self.scene.delete(f"{ROOT}/ellipsoids")
        for k in range(len(ells.points)):
            self.scene.set_transform(f"{ROOT}/ellipsoids/{k}", matrices[k])
        self.ellipsoids = ells
        self._colormap, self._range = colormap, (vmin, vmax)
        self._recolor()
        return ells

    def clear_ellipsoids(self) -> None:
        """Remove the ellipsoids of :meth:`add_ellipsoids`."""
        self.scene.delete(f"{ROOT}/ellipsoids")
        self.ellipsoids = None
        self._range = (None, None)
        self._recolor()

    def add_path(self, points: ArrayLike, speeds: ArrayLike | None = None) -> None:
        """Draw a tool path through ``points`` [m], shape (N, 3) (decimated if long).

        With ``speeds``, the path speed at each point [m/s], shape (N,), the path
        is coloured by feed (:mod:`~orthoglide_pin.viewer.planned`) and the legend
        names the colours, in mm/min, up to the largest speed of all the points
        (not only of those drawn, when the path is decimated).
        """
        p = finite_rows("points", points, 3, "[m]")
        v = None if speeds is None else finite_vector("speeds", speeds, len(p), "[m/s]")
        top = None if v is None else float(v.max())
        if p.ndim == 2 and len(p) > MAX_PATH_POINTS:
            k = np.unique(np.linspace(0, len(p) - 1, MAX_PATH_POINTS).round().astype(int))
            p, v = p[k], None if v is None else v[k]
        rgb = None if v is None else planned.feed_colors(v, top)
        self.scene.set_object(f"{ROOT}/path", overlays.polyline(p, colors=rgb))
        self._items.pop("tool path", None)
        self._items = {k: c for k, c in self._items.items() if not k.startswith("feed ")}
        self._items.update(
            {"tool path": overlays.PATH_RGB} if v is None else planned.feed_legend(v, top)
        )
        self._legend()

    # ------------------------------------------------------------ animation
    def play(
        self,
        trajectory: Any,
        *,
        fps: float = animation.DEFAULT_FPS,
        time_scale: float = 1.0,
        follow: str | None = "velocity",
        scale: float = overlays.ELLIPSOID_SCALE,
        colormap: str | None = None,
        loop: bool = True,
        path: bool = True,
    ) -> animation.Frames:
        """Animate a trajectory: every leg moves with its loops closed, frame by frame.

        Args:
            trajectory: Times ``t`` [s], shape (N,), and tool points ``p`` [m],
                shape (N, 3): a :class:`~orthoglide_pin.motion.trajectory.Trajectory`,
                a planned one (:func:`~orthoglide_pin.viewer.planned.read_trajectory`,
                its path coloured by feed) or a pair ``(t, p)``.
            fps: Frame rate of the animation [1/s] (lowered for long trajectories).
            time_scale: Animation time over trajectory time (2: half speed).
            follow: Kind of the ellipsoid that follows the tool (``"velocity"``,
                ``"force"``), or ``None`` for none. Its colours are on the
                legend's scale, shared with :meth:`add_ellipsoids`: the range
                grows to cover the condition numbers along the path (unless
                it was fixed there), so the follower's colour never leaves it.
            scale: Drawing scale of that ellipsoid [m per unit semi-axis].
            colormap: Colormap of the condition number (default: the one of
                :meth:`add_ellipsoids`, else ``"cool"``); it applies to every
                ellipsoid drawn.
            loop: Play over and over (else once).
            path: Also draw the tool path.

        Returns:
            The frames of the animation.
        """
        loop, path = flag("loop", loop), flag("path", path)
        follow = None if follow is None else overlays.check_kind(follow, "follow")
        t, p = animation.samples(trajectory)
        frames = animation.resample(t, p, fps, time_scale=time_scale)
        configurations = self.model.configuration(frames.points)
        placements = self.drawing.placements(configurations)
        builder = animation.AnimationBuilder(frames)
        for i, visual in enumerate(self.drawing.visuals):
            m = placements[:, i]
            if not np.allclose(m, m[0], rtol=0.0, atol=1e-12):
                builder.transforms(f"{ROOT}/machine/{visual.name}", m)
        if colormap is not None:
            overlays.colors([1.0], 0.0, 1.0, colormap)  # an unknown colormap fails here
        follower = None
        if follow is not None:
            scale = positive_number("scale", scale, "a positive number")
            follower = overlays.ellipsoids(
                frames.points, self.model.params.leg_length, follow, self.model.params
            )
            mats = overlays.ellipsoid_matrix(
                follower.points, follower.axes, follower.directions, scale
            )
            builder.transforms(f"{ROOT}/follower", mats, scale=True)
        self.scene.delete(f"{ROOT}/follower")
        if follower is not None:
            self.scene.set_transform(f"{ROOT}/follower", mats[0])
        if path:  # a planned trajectory's path coloured by its feed
            self.add_path(p, getattr(trajectory, "path_speed", None))
        self.show(configurations[0])
        repetitions = animation.LOOP_REPETITIONS if loop else 1
        self.follower, self._animation = follower, (builder, repetitions)
        self._colormap = colormap or self._colormap
        self.scene.set_animation(builder.animation, play=True, repetitions=repetitions)
        self._recolor()  # the follower's colour track, on the shared scale
        return frames

    def play_mode(self, point: ArrayLike, mode: int, **options: Any) -> modes.ModeMotion:
        """Animate the machine oscillating in a natural mode at ``point`` [m], over and over.

        Args:
            point: The tool point [m], shape (3,), in the machine's cube.
            mode: The mode's number, 1 for the lowest.
            **options: ``drive``, ``vibration_model``, ``amplitude`` [m] and
                ``period`` [s] of :func:`~orthoglide_pin.viewer.modes.mode_motion`.

        Returns:
            The motion drawn (see :mod:`~orthoglide_pin.viewer.modes`).
        """
        motion = modes.mode_motion(self.model, point, mode, **options)
        builder = animation.AnimationBuilder(motion.frames)
        for name, matrices in motion.placements(self.drawing).items():
            builder.transforms(f"{ROOT}/machine/{name}", matrices)
        self.scene.delete(f"{ROOT}/follower")
        self.follower, self._animation = None, None
        self.show(motion.configurations[0])
        ends = motion.point + motion.scale * np.outer([-1.0, 1.0], motion.direction)
        self.scene.set_object(f"{ROOT}/mode", overlays.polyline(ends, MODE_RGB))
        self._items = {k: c for k, c in self._items.items() if not k.startswith("mode ")}
        self._items[
            f"mode {motion.mode}: {motion.frequency:.1f} Hz, tool swing "
            f"{1e3 * motion.scale:.1f} mm drawn"
        ] = MODE_RGB
        self.scene.set_animation(
            builder.animation, play=True, repetitions=animation.LOOP_REPETITIONS
        )
        self._recolor()
        return motion

    def __repr__(self) -> str:
        where = self.url() or "not serving"
        return f"<Viewer of {len(self.drawing)} visuals, {where}>"
