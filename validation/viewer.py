r"""``deformable view``: a scene running in a window, the paper's two parameter groups as sliders (issue 29).

The paper's aim is "a more intuitive interface" to its two functionally independent parameter sets,
macro-control (mu, gamma and the forces f, section 3.1) and micro-control (eta, xi, sections 3.2, 4). The
window runs a scene as it is computed and gives each parameter a slider, grouped as the paper groups them:
on the left the macro group (mu, gamma and ``scale``, the factor on every applied force), on the right the
micro group (eta, xi). A slider changes the material of the running simulation: the scene is rebuilt with
the new value and the motion goes on from the same state (positions, velocities, time). Each slider spans
1/30 to 30 times the scene's value on a logarithmic scale (the value it shows).

Shown live, upper left: the simulated time, the elastic and kinetic energy (J), the largest fibre stretch
(every grid segment against its rest length, :meth:`deformable.Sheet.fibre_stretch`) and the paper's
compatibility test (section 3.2, eq. (10); :func:`deformable.geometry.check_compatibility`) on the current
G and B: the worst ratio and cosine of its first comparison where the compared vectors are resolved, else
its residual. A surface's own G and B pass the test up to the discretisation error, so the numbers show
how far the discrete tensors are from coherent.

Keys: space pauses and resumes, ``r`` resets the scene to its start and its sliders' values, ``g`` starts and
stops recording the frames to ``--gif`` (default ``<scene>.gif``). ``--offscreen --frames N --screenshot
FILE`` runs N frames without a window and saves the last one (scripts, tests).

Each frame advances ``1 / fps`` s of simulated time in the scene's steps; :class:`Session` is the simulation
behind the window, usable without one.
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass

import numpy as np

import deformable as dm
from deformable import scenes
from deformable.checks import extra
from deformable.errors import DivergenceError, InputError, StalledError
from deformable.geometry import check_compatibility

from .harness.backends import backend_dt, make_model

__all__ = ["Knob", "MACRO", "MICRO", "Session", "Readout", "Window"]


@dataclass(frozen=True)
class Knob:
    """A slider: the config field ``name``, its ``label`` (with the unit), spanning value / span .. value * span."""

    name: str
    label: str
    span: float = 30.0


#: the paper's macro-control (section 3.1): inertia, damping and the force scale
MACRO = (Knob("mu", "mu (kg/m^2)"), Knob("gamma", "gamma (kg/(m^2 s))"), Knob("scale", "force scale f (x)"))
#: the paper's micro-control (sections 3.2, 4): the weights of the energy (13)
MICRO = (Knob("eta", "eta (N/m)"), Knob("xi", "xi (N m)"))


@dataclass(frozen=True)
class Readout:
    """What the window shows of a state: t (s), elastic and kinetic energy (J), the largest fibre stretch,
    the compatibility test's worst ratio and cosine (None where no compared vector is resolved) or residual,
    its verdict, and the run's status ("running", "diverged", "stalled")."""

    t: float
    elastic: float
    kinetic: float
    stretch: float
    ratio: float | None
    cosine: float | None
    residual: float
    verdict: str
    status: str

    def text(self) -> str:
        test = (f"ratio {self.ratio:.4f}, cosine {self.cosine:.4f}" if self.ratio is not None
                else f"residual {self.residual:.3g}")
        return (f"t = {self.t:.3f} s   {self.status}\nenergy: elastic {self.elastic:.4g} J, kinetic {self.kinetic:.4g} J\n"
                f"largest stretch {100 * self.stretch:.2f} %\ncompatibility (eq. 10): {test} ({self.verdict})")


class Session:
    """A scene's simulation that a slider can change while it runs.

    Parameters
    ----------
    config : deformable.scenes.SceneConfig
    backend : "fd" or "fe"
    """

    def __init__(self, config, backend: str = "fd"):
        self.config0, self.backend = config, backend
        self.reset()

    def reset(self) -> None:
        """Back to the scene's start and its own parameters."""
        self._build(self.config0)
        self.state = self.stepper.start(self.X0)
        self.status = "running"

    def _build(self, config) -> None:
        self.config = config
        self.model = make_model(scenes.build(config), self.backend)
        self.stepper = dm.TimeStepper(self.model, backend_dt(self.model, config.dt))
        self.X0 = self.model.initial_state()

    def set(self, **values) -> None:
        """Change config fields (a slider) and go on from the current state; InputError on a bad value."""
        state = self.state
        self._build(self.config.replace(**values))
        self.stepper.start(self.X0)  # the constraints' reference positions, as at the start
        self.state = state

    def value(self, name: str) -> float:
        return float(getattr(self.config, name))

    def advance(self, seconds: float) -> None:
        """Step the simulation by ``seconds`` of simulated time (whole steps); stops for good on divergence."""
        if self.status != "running":
            return
        target = self.state.t + seconds
        try:
            while self.state.t < target - 1e-12:
                self.state = self.stepper.step(self.state)
        except DivergenceError as err:
            self.status, self.state = "diverged", err.state
        except StalledError as err:
            self.status, self.state = "stalled", err.state

    def points(self) -> np.ndarray:
        """The sheet's node positions (M, N, 3)."""
        return self.model.grid(self.state.X)

    def speed(self) -> np.ndarray:
        """|v| at the nodes (M, N)."""
        return np.linalg.norm(self.model.grid(self.state.V), axis=-1)

    def readout(self) -> Readout:
        X, V = self.state.X, self.state.V
        e = self.model.energy(X)
        s1, s2 = self.model.scene.sheet.fibre_stretch(self.model.grid(X))
        G, B = self.model.tensors(X)
        test = check_compatibility(G, B, self.model.scene.sheet.h)
        c = next(iter(test.comparisons.values()))
        return Readout(t=self.state.t, elastic=float(e.stretching + e.bending), kinetic=float(self.model.kinetic_energy(V)),
                       stretch=float(max(s1.max(), s2.max())), ratio=c.ratio[0] if c.ratio else None,
                       cosine=c.cosine[0] if c.cosine else None, residual=float(c.residual), verdict=test.verdict,
                       status=self.status)


def _pyvista(offscreen: bool):
    pyvista = extra("pyvista", "render", "deformable view")
    if offscreen:
        from deformable.io.render import offscreen_pyvista

        return offscreen_pyvista()
    if not os.environ.get("DISPLAY"):
        raise InputError("deformable view: no display (DISPLAY is not set); run it under a desktop or xvfb-run, or "
                         "give --offscreen --frames N --screenshot FILE")
    return pyvista


class Window:
    """The pyvista window on a :class:`Session` (module docstring).

    Parameters
    ----------
    session : Session
    offscreen : bool
        Render without a window (``--offscreen``).
    fps : float
        Frames a simulated second; each frame advances 1 / fps s.
    gif : str or path, optional
        Where ``g`` records to.
    """

    def __init__(self, session: Session, offscreen: bool = False, fps: float = 30.0, gif=None, size=(1100, 760)):
        self.session, self.fps, self.paused, self.recording, self.top = session, fps, False, False, 1.0
        self.gif = str(gif or f"{session.config.scene}.gif")
        pv = self.pv = _pyvista(offscreen)
        self.plotter = pv.Plotter(off_screen=offscreen, window_size=size, title=f"deformable view {session.config.scene}")
        P = session.points()
        self.mesh = pv.StructuredGrid(P[..., 0], P[..., 1], P[..., 2])
        self.mesh["speed (m/s)"] = session.speed().ravel(order="F")
        self.plotter.add_mesh(self.mesh, scalars="speed (m/s)", cmap="viridis", clim=(0.0, 1.0), smooth_shading=True,
                              scalar_bar_args=dict(title="speed (m/s)\n", vertical=True, position_x=0.9, position_y=0.06,
                                                   height=0.38, width=0.05, color="black", n_labels=3,
                                                   fmt="%.2g"))
        from deformable.io.render import camera, obstacle_mesh

        lo, hi = P.reshape(-1, 3).min(0), P.reshape(-1, 3).max(0)
        pad = 0.3 * float(np.max(hi - lo))
        for obstacle in session.model.scene.obstacles:
            self.plotter.add_mesh(obstacle_mesh(obstacle, np.array([lo, hi])), color="lightgrey", smooth_shading=True)
        self.plotter.camera_position = camera(np.array([lo - pad, hi + pad]))
        self.plotter.set_background("white")
        self.sliders = {}
        for group, knobs, x0 in (("macro-control", MACRO, 0.02), ("micro-control", MICRO, 0.70)):
            self.plotter.add_text(group, position=(int(x0 * size[0]), int(0.84 * size[1])), font_size=10,
                                  color="black")
            for k, knob in enumerate(knobs):
                self._slider(knob, x0, 0.79 - 0.1 * k)
        self.plotter.add_text(session.readout().text(), position="upper_left", font_size=9, color="black",
                              name="readout")
        self.plotter.add_key_event("space", self.toggle_pause)
        self.plotter.add_key_event("r", self.reset)
        self.plotter.add_key_event("g", self.toggle_gif)

    def _slider(self, knob: Knob, x0: float, y: float) -> None:
        v0 = self.session.value(knob.name)
        if not v0 > 0:  # a zero weight (xi = 0): the slider starts from a small value instead
            v0 = {"xi": 1e-6, "eta": 1.0, "gamma": 0.01}.get(knob.name, 1.0)
        lo, hi = math.log10(v0 / knob.span), math.log10(v0 * knob.span)

        def moved(value, knob=knob):
            if knob.name in self.sliders and not math.isclose(10.0**value, self.session.value(knob.name), rel_tol=1e-9):
                self.set(knob.name, 10.0**value)  # (pyvista calls it once as the slider is made: nothing moved)

        w = self.plotter.add_slider_widget(moved, (lo, hi), value=math.log10(max(self.session.value(knob.name), v0)),
                                           title=self._title(knob), pointa=(x0, y), pointb=(x0 + 0.26, y),
                                           style="modern", interaction_event="end", fmt=" ", title_height=0.018,
                                           title_color="black")
        self.sliders[knob.name] = (knob, w)

    def _title(self, knob: Knob) -> str:
        return f"{knob.label} = {self.session.value(knob.name):.3g}"

    def set(self, name: str, value: float) -> None:
        """A slider moved: the running simulation takes ``value`` for the field ``name``."""
        self.session.set(**{name: value})
        knob, w = self.sliders[name]
        w.GetRepresentation().SetTitleText(self._title(knob))

    def move(self, name: str, value: float) -> None:
        """Move a slider as a hand would (its widget's representation, then its end-of-interaction event)."""
        import vtk

        _, w = self.sliders[name]
        w.GetRepresentation().SetValue(math.log10(value))
        w.InvokeEvent(vtk.vtkCommand.EndInteractionEvent)

    def toggle_pause(self) -> None:
        self.paused = not self.paused

    def reset(self) -> None:
        self.session.reset()
        for name, (knob, w) in self.sliders.items():
            w.GetRepresentation().SetValue(math.log10(self.session.value(name)))
            w.GetRepresentation().SetTitleText(self._title(knob))
        self.update()

    def toggle_gif(self) -> None:
        if self.recording:
            self.plotter.mwriter.close()
        else:
            self.plotter.open_gif(self.gif)
        self.recording = not self.recording

    def update(self) -> None:
        P = self.session.points()
        self.mesh.points = P.reshape(-1, 3, order="F")
        speed = self.session.speed()
        self.mesh["speed (m/s)"] = speed.ravel(order="F")
        if speed.max() > self.top:  # the colour range only grows (by doublings), so frames stay comparable
            self.top = 2.0 ** math.ceil(math.log2(speed.max()))
            self.plotter.update_scalar_bar_range((0.0, self.top))
        self.plotter.add_text(self.session.readout().text(), position="upper_left", font_size=9, color="black",
                              name="readout")

    def frame(self) -> None:
        """One frame: 1 / fps s of simulated time (unless paused), redrawn."""
        if not self.paused:
            self.session.advance(1.0 / self.fps)
        self.update()
        self.plotter.render()
        if self.recording:
            self.plotter.write_frame()

    def run(self, frames: int | None = None, screenshot=None) -> float:
        """``frames`` frames (None: until the window closes), then ``screenshot`` (PNG) of the last; returns the
        wall time (s) the frames took."""
        start = time.perf_counter()
        if frames is not None:
            if not self.plotter.off_screen:  # a real window opens before its first frame
                self.plotter.show(auto_close=False, interactive=False)
            for _ in range(frames):
                self.frame()
        else:
            self.plotter.add_timer_event(max_steps=10**9, duration=max(1, int(1000 / self.fps)),
                                         callback=lambda step: self.frame())
            self.plotter.show(auto_close=False)
        wall = time.perf_counter() - start
        if screenshot is not None:
            self.plotter.screenshot(str(screenshot))
        if self.recording:
            self.toggle_gif()
        self.plotter.close()
        return wall
