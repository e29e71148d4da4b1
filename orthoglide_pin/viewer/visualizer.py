"""The viewer: the machine, its overlays and animations in a browser (meshcat).

:class:`Viewer` draws a closed-loop model from its URDF's visuals
(:mod:`~orthoglide_pin.viewer.machine`), adds overlays
(:mod:`~orthoglide_pin.viewer.overlays`) and plays trajectories
(:mod:`~orthoglide_pin.viewer.animation`). Everything is recorded in a
:class:`~orthoglide_pin.viewer.scene.Scene` without any server, so a scene can
be built and exported to one self-contained HTML file headless
(:meth:`Viewer.save_html`), shown inline in a notebook (``_repr_html_``), or
served live on 127.0.0.1 (:meth:`Viewer.serve`), where later changes reach the
open pages at once.

Scene layout (meshcat paths): the machine under ``/meshcat/orthoglide/machine``,
overlays under ``/meshcat/orthoglide/{workspace,ellipsoids,path,follower}``.
The root node shifts the scene so that the machine's centre sits at the
viewer's origin, the point the camera orbits; coordinates below it are the
machine's world frame [m] (origin at the tool tip at home).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import atomic_write_text
from orthoglide_pin._validation import positive_number
from orthoglide_pin.viewer import animation, overlays
from orthoglide_pin.viewer.html import iframe_html, static_html
from orthoglide_pin.viewer.machine import MachineDrawing
from orthoglide_pin.viewer.scene import Scene, meshcat

if TYPE_CHECKING:
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.viewer.server import SceneServer

FloatArray = NDArray[np.float64]

#: Root of everything the viewer draws.
ROOT: Final[str] = "/meshcat/orthoglide"
#: meshcat's default camera (its parent turns three.js's y-up into z-up).
CAMERA: Final[str] = "/Cameras/default/rotated/<object>"
#: Direction from the scene's centre to the camera, world frame.
VIEW_DIRECTION: Final = (1.0, 0.8, 0.6)
#: Camera distance over the distance at which the machine's bounding sphere fills the view.
FRAMING: Final[float] = 0.9
#: Vertical field of view of meshcat's default camera [deg].
CAMERA_FOV: Final[float] = 75.0
#: Background gradient (RGB in [0, 1]): white to a light grey.
BACKGROUND: Final = ((1.0, 1.0, 1.0), (0.84, 0.86, 0.89))
#: Length of the world-frame triad drawn at the origin [m].
TRIAD_LENGTH: Final[float] = 0.05
#: Most points drawn for a tool path.
MAX_PATH_POINTS: Final[int] = 4000


class Viewer:
    """The Orthoglide in a browser: machine, overlays, animations (meshcat).

    Building a viewer starts no server: see :meth:`serve`.

    Args:
        model: The closed-loop model; the prototype's when ``None``.
        title: Title of the page.

    Attributes:
        model: The closed-loop model.
        scene: The recorded scene.
        drawing: The machine's visuals.
        configuration: The configuration shown [m, rad], shape (18,).
        ellipsoids: The ellipsoids drawn by :meth:`add_ellipsoids`, or ``None``.
    """

    def __init__(
        self,
        model: ClosedLoopModel | None = None,
        *,
        title: str = "Orthoglide",
    ) -> None:
        if model is None:
            from orthoglide_pin.machine.closed_loop import ClosedLoopModel

            model = ClosedLoopModel()
        self.model = model
        self.title = title
        self.scene = Scene()
        self.drawing = MachineDrawing(model)
        self.configuration = model.neutral()
        self.ellipsoids: overlays.Ellipsoids | None = None
        self._server: SceneServer | None = None
        self._items: dict[str, Any] = {}
        self._bars: dict[str, tuple[str, float, float, str]] = {}
        self._setup()

    def _setup(self) -> None:
        s = self.scene
        s.set_property("/Background", "top_color", list(BACKGROUND[0]))
        s.set_property("/Background", "bottom_color", list(BACKGROUND[1]))
        s.set_property("/Grid", "visible", False)
        s.set_property("/Axes", "visible", False)
        self.drawing.draw(s, ROOT, self.configuration)
        s.set_object(f"{ROOT}/world_axes", meshcat("geometry").triad(TRIAD_LENGTH).lower())
        self._frame()

    def _frame(self) -> None:
        """Centre the machine at home and its workspace on the viewer's origin, camera on it."""
        lower, upper = self.drawing.bounds(self.model.neutral())
        corner, side = self.workspace_cube()
        lower, upper = np.minimum(lower, corner), np.maximum(upper, corner + side)
        centre, radius = 0.5 * (lower + upper), 0.5 * float(np.linalg.norm(upper - lower))
        self.scene.set_transform(ROOT, overlays.translation(-centre))
        distance = FRAMING * radius / math.sin(math.radians(CAMERA_FOV / 2))
        d = np.asarray(VIEW_DIRECTION) / np.linalg.norm(VIEW_DIRECTION)
        w = distance * d  # world frame; the camera's parent is Rx(pi/2): (x, z, -y)
        self.scene.set_property(CAMERA, "position", [float(w[0]), float(w[2]), float(-w[1])])

    def _legend(self) -> None:
        bar = next(iter(self._bars.values()), None)
        self.scene.set_legend(overlays.legend(self._items, bar) if self._items or bar else None)

    # -------------------------------------------------------------- machine
    def show(self, configuration: ArrayLike) -> None:
        """Show a configuration of the 18 joints [m, rad] (its loops closed)."""
        q = np.asarray(configuration, dtype=float)
        self.drawing.place(self.scene, ROOT, q)
        self.configuration = q.copy()

    def show_point(self, point: ArrayLike) -> FloatArray:
        """Show the machine with its tool at ``point`` [m]; return the configuration (18,)."""
        q = self.model.configuration(point)
        self.show(q)
        return q

    def show_sliders(self, q_actuated: ArrayLike) -> FloatArray:
        """Show the machine for slider values [m], loops closed by Newton; return (18,)."""
        q = self.model.solve(q_actuated, self.configuration).q
        self.show(q)
        return q

    # ------------------------------------------------------------- overlays
    def workspace_cube(self) -> tuple[FloatArray, float]:
        """The prototype's cube scaled to this machine: lower corner [m], (3,), and side [m]."""
        from orthoglide_pin.kinetostatics.design import prototype_cube

        return prototype_cube(self.model.params)

    def add_workspace(
        self, corner: ArrayLike | None = None, side: float | None = None, *, markers: bool = True
    ) -> None:
        """Draw the workspace cube (wireframe) and mark the isotropic point, Q1 and Q2.

        Args:
            corner: Lowest corner Q1 [m], shape (3,); by default the prototype's
                cube for this machine (:meth:`workspace_cube`).
            side: Side [m] (Q2 = Q1 + side (1, 1, 1)).
            markers: Also draw the three points.
        """
        default_corner, default_side = self.workspace_cube()
        c = default_corner if corner is None else np.asarray(corner, dtype=float)
        h = default_side if side is None else float(side)
        self.scene.set_object(f"{ROOT}/workspace/cube", overlays.cube_wireframe(c, h))
        self._items["workspace cube"] = overlays.CUBE_RGB
        if markers:
            where = {"isotropic point": np.zeros(3), "Q1": c, "Q2": c + h}
            for name, point in where.items():
                path = f"{ROOT}/workspace/{name.replace(' ', '_')}"
                rgb = overlays.MARKER_RGB[name]
                self.scene.set_object(path, overlays.sphere(overlays.MARKER_RADIUS, rgb))
                self.scene.set_transform(path, overlays.translation(point))
                self._items[name] = rgb
        self._legend()

    def grid_points(self, n: int = 3) -> FloatArray:
        """``n^3`` points spanning the workspace cube [m], shape (n^3, 3)."""
        from orthoglide_pin.kinetostatics.workspace import cube_grid

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

        Replaces the ellipsoids drawn before.

        Args:
            points: Tool points [m], shape (3,) or (N, 3).
            kind: ``"velocity"`` (semi-axes: transmission factors) or ``"force"``.
            scale: Drawing scale [m per unit semi-axis].
            colormap: matplotlib colormap of the condition number.
            vmin: Condition number at the colormap's start (default 1).
            vmax: Condition number at its end (default: the largest drawn).

        Returns:
            The ellipsoids drawn.
        """
        scale = positive_number("scale", scale, "a positive number")
        ells = overlays.ellipsoids(points, self.model.params.leg_length, kind)
        lo, hi = overlays.color_range(ells.condition, vmin, vmax)
        rgb = overlays.colors(ells.condition, lo, hi, colormap)
        matrices = overlays.ellipsoid_matrix(ells.points, ells.axes, ells.directions, scale)
        self.scene.delete(f"{ROOT}/ellipsoids")
        for k in range(len(ells.points)):
            path = f"{ROOT}/ellipsoids/{k}"
            self.scene.set_object(path, overlays.sphere(1.0, rgb[k]))
            self.scene.set_transform(path, matrices[k])
        self.ellipsoids = ells
        self._bars["ellipsoids"] = (f"condition number ({kind} ellipsoids)", lo, hi, colormap)
        self._legend()
        return ells

    def clear_ellipsoids(self) -> None:
        """Remove the ellipsoids of :meth:`add_ellipsoids`."""
        self.scene.delete(f"{ROOT}/ellipsoids")
        self.ellipsoids = None
        self._bars.pop("ellipsoids", None)
        self._legend()

    def add_path(self, points: ArrayLike) -> None:
        """Draw a tool path through ``points`` [m], shape (N, 3) (decimated if long)."""
        p = np.asarray(points, dtype=float)
        if p.ndim == 2 and len(p) > MAX_PATH_POINTS:
            p = p[np.unique(np.linspace(0, len(p) - 1, MAX_PATH_POINTS).round().astype(int))]
        self.scene.set_object(f"{ROOT}/path", overlays.polyline(p))
        self._items["tool path"] = overlays.PATH_RGB
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
        colormap: str = overlays.COLORMAP,
        loop: bool = True,
        path: bool = True,
    ) -> animation.Frames:
        """Animate a trajectory: every leg moves with its loops closed, frame by frame.

        Args:
            trajectory: Times ``t`` [s], shape (N,), and tool points ``p`` [m],
                shape (N, 3): a :class:`~orthoglide_pin.motion.trajectory.Trajectory`
                or a pair ``(t, p)``.
            fps: Frame rate of the animation [1/s] (lowered for long trajectories).
            time_scale: Animation time over trajectory time (2: half speed).
            follow: Kind of the ellipsoid that follows the tool (``"velocity"``,
                ``"force"``), or ``None`` for none. Its colour range is that
                of the ellipsoids of :meth:`add_ellipsoids` if any, else 1 to
                the largest condition number along the path.
            scale: Drawing scale of that ellipsoid [m per unit semi-axis].
            colormap: Colormap of its condition number.
            loop: Play over and over (else once).
            path: Also draw the tool path.

        Returns:
            The frames of the animation.
        """
        t, p = animation.samples(trajectory)
        frames = animation.resample(t, p, fps, time_scale=time_scale)
        configurations = self.model.configuration(frames.points)
        placements = self.drawing.placements(configurations)
        builder = animation.AnimationBuilder(frames)
        for i, visual in enumerate(self.drawing.visuals):
            m = placements[:, i]
            if not np.allclose(m, m[0], rtol=0.0, atol=1e-12):
                builder.transforms(f"{ROOT}/machine/{visual.name}", m)
        self.scene.delete(f"{ROOT}/follower")
        self._bars.pop("follower", None)
        if follow is not None:
            scale = positive_number("scale", scale, "a positive number")
            ells = overlays.ellipsoids(frames.points, self.model.params.leg_length, follow)
            shared = self._bars.get("ellipsoids")
            lo, hi = shared[1:3] if shared else overlays.color_range(ells.condition)
            rgb = overlays.colors(ells.condition, lo, hi, colormap)
            mats = overlays.ellipsoid_matrix(ells.points, ells.axes, ells.directions, scale)
            where = f"{ROOT}/follower"
            self.scene.set_object(where, overlays.sphere(1.0, rgb[0]))
            self.scene.set_transform(where, mats[0])
            builder.transforms(where, mats, scale=True)
            builder.colors(f"{where}/<object>", rgb)
            self._bars["follower"] = (f"condition number ({follow} ellipsoid)", lo, hi, colormap)
        if path:
            self.add_path(p)
        self.show(configurations[0])
        repetitions = animation.LOOP_REPETITIONS if loop else 1
        self.scene.set_animation(builder.animation, play=True, repetitions=repetitions)
        self._legend()
        return frames

    # --------------------------------------------------------------- output
    def html(self) -> str:
        """The scene as one self-contained HTML page (works offline, no server)."""
        return static_html(self.scene, title=self.title)

    def save_html(self, path: str | Path) -> Path:
        """Write :meth:`html` to ``path`` atomically; return the path."""
        target = Path(path)
        atomic_write_text(target, self.html())
        return target

    def iframe(self, height: int = 500) -> str:
        """The static page in an iframe, for a notebook cell (``height`` pixels)."""
        return iframe_html(self.html(), height=height)

    def _repr_html_(self) -> str:
        link = ""
        if self.url() is not None:
            link = f'<p>Live viewer: <a href="{self.url()}" target="_blank">{self.url()}</a></p>'
        return self.iframe() + link

    # --------------------------------------------------------------- server
    def serve(self, port: int = 7000) -> str:
        """Serve the scene live on ``http://127.0.0.1:<port>/`` (background thread).

        Later changes to the scene reach the open pages at once. ``port`` 0
        picks a free port.

        Returns:
            The URL.

        Raises:
            PortInUseError: If the port is in use.
        """
        from orthoglide_pin.viewer.server import SceneServer

        if self._server is None or not self._server.running:
            self._server = SceneServer(self.scene, port, title=self.title)
            self._server.start()
        return self._server.url

    def serve_forever(self, port: int = 7000) -> None:
        """Serve until Ctrl-C, then shut down cleanly (call from the main thread)."""
        self.serve(port)
        assert self._server is not None
        self._server.serve_forever()

    def url(self) -> str | None:
        """The live server's URL, or ``None`` when not serving."""
        return self._server.url if self._server is not None and self._server.running else None

    def close(self) -> None:
        """Stop the live server, if any (idempotent)."""
        if self._server is not None:
            self._server.close()
            self._server = None

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        where = self.url() or "not serving"
        return f"<Viewer of {len(self.drawing)} visuals, {where}>"
