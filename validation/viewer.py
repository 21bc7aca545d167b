r"""``deformable view``: a scene running in a window, the paper's two parameter groups as sliders (issue 29).

The paper's aim is "a more intuitive interface" to its two functionally independent parameter sets,
macro-control (mu, gamma and the forces f, section 3.1) and micro-control (eta, xi, sections 3.2, 4). The
window runs a scene as it is computed and gives each parameter a slider, grouped as the paper groups them:
on the left the macro group (mu, gamma and ``scale``, the factor on every applied force), on the right the
micro group (eta, xi). A slider changes the material of the running simulation: the model is rebuilt with the
new value and the running stepper takes it (:meth:`deformable.TimeStepper.retune`: the Newton solver, its
matrix's pattern and the factorisation's analysis are kept, only the values are refilled), and the motion goes
on from the same state (positions, velocities, time). Each slider spans 1/30 to 30 times the scene's value on a
logarithmic scale; its title shows the value in effect in the frame on screen.

Shown live, upper left: the simulated time, the elastic and kinetic energy (J), the largest fibre stretch
(every grid segment against its rest length, :meth:`deformable.Sheet.fibre_stretch`) and the paper's
compatibility test (section 3.2, eq. (10)). The test asks whether given G and B are those of a surface, which is
a question about the rest state G0, B0 a user gives (:func:`deformable.geometry.check_rest_state`, on the rest
tensors at least 33 points a side): its verdict is shown, "INCOMPATIBLE" where no surface has them. A state of
the simulation is a surface by construction (its G and B are computed from its positions), so the test on it
measures only its own discretisation error: the window shows the test's mismatch (the largest ``|u - v|`` over the
compared vectors' scale, :attr:`~deformable.geometry.compatibility.Compatibility.mismatch_relative`) on the
state at h and on every second node at 2h, and calls the state a surface, never incompatible. Measured on the
shipped curtain (FD 20 x 20, every 0.1 s over 2 s): the mismatch 0.12 to 1.66 at h and 0.09 to 1.32 at 2h, the
paper's test failing at every deformed state: its folds are a few grid spacings wide, and neither grid resolves
the third derivatives the test compares (the paper study, "says little about a deformed state"). The test is the
readout's costly part (G, B and their derivatives: about 2 ms of CPU a frame at 20 x 20 nodes), so the window
takes it at most every :data:`READOUT_EVERY` s of simulated time and, in between, shows the last one with the
time it was taken at.

The macro sliders show what they change: ``scale`` (the force scale f, section 3.1) multiplies mu, gamma and
every applied force, so the mu and gamma sliders' titles show the values in effect, f times the real-world
value their slider sets, and move when f does.

Simulation and drawing are decoupled (the window in real time). The simulation is a :class:`Producer`: it
computes the states at the frame times, ``1 / fps`` s apart, and hands the newest one (positions, speeds,
readout: a :class:`Frame`) over; the window draws the newest frame there is, never waiting for the simulation.
A slider, pause, reset or quit is a command that the producer applies between two steps (a queue), so the
stepper is never changed during a step. In the interactive window the producer runs in a thread of its own,
paced to real time when it is faster, and the window runs its own loop at twice the frame rate (its events, the
newest frame drawn if there is a new one, a sleep). The step's kernels (Numba's ``nogil`` kernels, PARDISO
through ctypes, numpy and SciPy) and VTK's rendering release the GIL, so simulation and drawing use two cores;
VTK's own event loop does not (a simulation thread beside it ran eight times slower than alone), hence the
window's loop in Python. Closing the window (``q``, ``e`` or its close button) stops the thread at its next
step boundary. With ``--frames N`` (``--offscreen``, scripts, tests) the calling thread runs simulation and
drawing in turn, frame by frame: the same frames, deterministically.

Keys: space pauses and resumes, ``r`` resets the scene to its start and its sliders' values, ``g`` starts and
stops recording the frames to ``--gif`` (default ``<scene>.gif``). ``--offscreen --frames N --screenshot
FILE`` runs N frames without a window (each frame rendered off screen, as a window would) and saves the last
one. :class:`Session` is the simulation behind the window, usable without one.
"""

from __future__ import annotations

import collections
import logging
import math
import os
import threading
import time
from dataclasses import dataclass

import numpy as np

import deformable as dm
from deformable import scenes
from deformable.checks import extra
from deformable.errors import DivergenceError, InputError, StalledError
from deformable.geometry import check_compatibility
from deformable.geometry.compatibility import check_rest_state

from deformable.session import Simulation

__all__ = ["FPS", "MACRO", "MICRO", "READOUT_EVERY", "Frame", "Knob", "Producer", "Readout", "Session", "Window"]

log = logging.getLogger(__name__)

#: frames a simulated second (the ``--fps`` default)
FPS = 30.0
#: the readout's compatibility test is taken at most this often (s of simulated time): five times a simulated second
READOUT_EVERY = 0.2
#: a frame's target time counts as reached within this (s): whole steps accumulate rounding
_REACHED = 1e-9


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
    """What the window shows of a state: t (s), elastic and kinetic energy (J), the largest fibre stretch, the
    rest state's verdict under the paper's test (``rest``: "compatible", "INCOMPATIBLE", "NOT COMPUTABLE", or why
    it was not tested), the test's mismatch on the state at h and at 2h (``mismatch``, ``mismatch_2h``: the
    discrete test's own error on a surface; NaN, None where the grid is too small, ``note`` then says why), the
    run's status ("running", "diverged", "stalled") and ``tested_at``, the time (s) of the state the test was
    taken on (``t``, or earlier where it is reused: :data:`READOUT_EVERY`)."""

    t: float
    elastic: float
    kinetic: float
    stretch: float
    rest: str
    mismatch: float
    mismatch_2h: float | None
    note: str
    status: str
    tested_at: float
    dt: float = math.nan
    stable: float = math.inf
    fabric: str = ""
    resolution: str = ""

    def text(self) -> str:
        at = "" if self.tested_at == self.t else f" (at t = {self.tested_at:.3f} s)"
        if math.isnan(self.mismatch):
            state = f"not computed ({self.note})"
        else:
            coarse = f", {self.mismatch_2h:.3g} at 2h" if self.mismatch_2h is not None else ""
            state = f"a surface; the test's own error, mismatch {self.mismatch:.3g} at h{coarse}"
        fabric = f"   fabric {self.fabric}" if self.fabric else ""
        return (f"t = {self.t:.3f} s   {self.status}{fabric}\n"
                f"energy: elastic {self.elastic:.4g} J, kinetic {self.kinetic:.4g} J\n"
                f"largest stretch {100 * self.stretch:.2f} %\n"
                f"compatibility (eq. 10): rest state G0, B0 {self.rest}\n"
                f"  the state{at}: {state}" + self._stability()
                + (f"\n{self.resolution}" if self.resolution else ""))

    def _stability(self) -> str:
        """Where the scheme has a stable step (the paper's semi-implicit scheme, section 2.3): dt against it."""
        if not math.isfinite(self.stable):
            return ""
        return (f"\nstable step of the semi-implicit scheme {1e3 * self.stable:.3g} ms (h sqrt(mu / (2 eta G))): "
                f"dt = {1e3 * self.dt:.3g} ms")


@dataclass(frozen=True)
class _Test:
    """The compatibility test's mismatch on the state at ``t`` (s), at h and 2h (module docstring)."""

    t: float
    mismatch: float
    mismatch_2h: float | None
    note: str


def _mismatch(G, B, h) -> tuple[float, str]:
    """The paper's test's mismatch on (2, 2, M, N) fields G, B at spacing h, or NaN and why not."""
    try:
        return check_compatibility(G, B, h).mismatch_relative, ""
    except InputError as err:  # a grid under 6 nodes a side, or G not positive definite: said so
        return math.nan, str(err)


def rest_verdict(scene) -> str:
    """The rest state's verdict under the paper's test (:func:`deformable.geometry.check_rest_state`), or why
    it was not tested."""
    try:
        result = check_rest_state(scene)
    except InputError as err:
        return f"not tested ({err})"
    return result.verdict + (" (no surface has them)" if result.finite and not result.compatible else "")


class Session:
    """A scene's simulation that a slider can change while it runs.

    Not thread-safe: one thread at a time steps and changes it (the :class:`Producer`'s, while it runs).

    Parameters
    ----------
    config : deformable.scenes.SceneConfig
    backend : "fd" or "fe"
    """

    def __init__(self, config, backend: str = "fd"):
        self.config0, self.backend = config, backend
        self.reset()

    def reset(self) -> None:
        """Back to the scene's start and its own parameters (a stepper built anew)."""
        self._build(self.config0)
        self.state = self.stepper.start(self.X0)
        self.status = "running"
        self._test = None

    def _build(self, config) -> None:
        self.config = config
        sim = Simulation(config, self.backend, nodes=config.nodes)  # the grid, model and dt a run takes
        self.model = sim.model
        self.rest = rest_verdict(self.model.scene)
        self.stepper = sim.stepper
        self.stable, self.resolution = self._stable_step(), self._resolution()
        self.X0 = self.model.initial_state()

    def set(self, **values) -> None:
        """Change config fields (a slider) and go on from the current state; InputError on a bad value (then
        nothing changed).

        The running stepper takes the new model (:meth:`deformable.TimeStepper.retune`: same stepper, same Newton
        solver, its pattern and analysis kept). Only where the step itself moves with the material (the
        semi-implicit scheme's stable step, :func:`deformable.dynamics.dt.within_stable`) is a stepper built
        anew, on the same constraint reference.
        """
        values = self._with_fabric(values)
        config = self.config.replace(**{"nodes": self.config.nodes, **values})  # the running grid (a fabric's own
        # grid, where a scene picks one, is for a new run: the stepper is retuned on the same grid)
        sim = Simulation(config, self.backend, nodes=config.nodes)
        model, dt = sim.model, sim.config.dt
        if dt == self.stepper.dt:
            self.stepper.retune(model)
        else:
            log.info("deformable view: %s moves the stable step to dt = %g s; a new stepper", values, dt)
            stepper = sim.stepper
            stepper.start(self.stepper.reference)  # the constraints' reference positions, as at the start
            self.stepper = stepper
        self.config, self.model = config, model
        self.stable, self.resolution = self._stable_step(), self._resolution()

    def _with_fabric(self, values: dict) -> dict:
        """A change of the named fabric, or of a field it sets, as config changes: ``fabric=""`` is the scene's own
        material back (its fabric, or its mu, eta, xi and shear); a slider moving mu, eta, xi or shear while a
        fabric is on leaves the fabric for an isotropic sheet of its warp's values (the sliders' values) and the
        new one."""
        own = type(self.config).FABRIC_FIELDS
        if "fabric" in values and not values["fabric"]:
            if self.config0.fabric:
                return {"fabric": self.config0.fabric}
            return {**{f: getattr(self.config0, f) for f in own}, **values, "fabric": ""}
        if self.config.fabric and "fabric" not in values and set(values) & set(own):
            return {**{f: getattr(self.config, f) for f in own}, **values, "fabric": ""}
        return values

    def _resolution(self) -> str:
        """The grid against the folds, by ``deformable params``' criterion (:mod:`deformable.scenes.params`: the
        narrowest fold predicted, at least 3 grid spacings): a warning where the grid does not resolve them."""
        p = scenes.parameters(self.config, self.model, self.backend)
        if not math.isfinite(p.fold_scale) or p.resolved:
            return ""
        return (f"grid NOT resolving the folds: narrowest fold predicted {p.narrowest_fold / min(p.spacing):.2g} "
                f"grid spacings (at least 3 to resolve them; deformable params)")

    def _stable_step(self) -> float:
        """The stable step (s) of the stepper's scheme: the backend's bound where the scheme is the paper's
        semi-implicit one (eq. (25)), inf where it has none (implicit schemes)."""
        from deformable.dynamics.scheme import Scheme

        return math.inf if Scheme.lookup(self.stepper.scheme).implicit else float(self.model.stable_step())

    def value(self, name: str) -> float:
        return float(getattr(self.config, name))

    def advance_to(self, target: float, interrupt=None) -> bool:
        """Step (whole steps) until the time reaches ``target`` (s), or stop for good on divergence; returns False
        when ``interrupt()`` became true between two steps before that (the state is then a step boundary short of
        the target), True otherwise."""
        if self.status != "running":
            return True
        try:
            while self.state.t < target - _REACHED:
                if interrupt is not None and interrupt():
                    return False
                self.state = self.stepper.step(self.state)
        except DivergenceError as err:
            self.status, self.state = "diverged", err.state
        except StalledError as err:
            self.status, self.state = "stalled", err.state
        return True

    def advance(self, seconds: float) -> None:
        """Step the simulation by ``seconds`` of simulated time (whole steps); stops for good on divergence."""
        self.advance_to(self.state.t + seconds)

    def points(self) -> np.ndarray:
        """The sheet's node positions (M, N, 3) (m)."""
        return self.model.grid(self.state.X)

    def speed(self) -> np.ndarray:
        """|v| at the nodes (M, N) (m/s)."""
        return np.linalg.norm(self.model.grid(self.state.V), axis=-1)

    def readout(self, every: float = 0.0) -> Readout:
        """The readout of the current state. The compatibility test (G, B and their derivatives: the costly part)
        is taken anew unless the last one was taken at most ``every`` s of simulated time before (0: always); a
        reused one carries the time it was taken at (:attr:`Readout.tested_at`)."""
        X, V, t = self.state.X, self.state.V, self.state.t
        e = self.model.energy(X)
        s1, s2 = self.model.scene.sheet.fibre_stretch(self.model.grid(X))
        test = self._test
        if test is None or not 0.0 <= t - test.t < every:  # none yet, too old, or from before a reset
            G, B = self.model.tensors(X)
            h = np.broadcast_to(np.asarray(self.model.scene.sheet.h, float), (2,))
            fine, note = _mismatch(G, B, tuple(h))
            coarse, _ = _mismatch(G[:, :, ::2, ::2], B[:, :, ::2, ::2], tuple(2 * h)) if not note else (math.nan, "")
            test = self._test = _Test(t=t, mismatch=fine, mismatch_2h=None if math.isnan(coarse) else coarse,
                                      note=note)
        return Readout(t=t, elastic=float(e.stretching + e.bending), kinetic=float(self.model.kinetic_energy(V)),
                       stretch=float(max(s1.max(), s2.max())), rest=self.rest, mismatch=test.mismatch,
                       mismatch_2h=test.mismatch_2h, note=test.note, status=self.status, tested_at=test.t,
                       dt=self.stepper.dt, stable=self.stable, fabric=self.config.fabric,
                       resolution=self.resolution)


@dataclass(frozen=True)
class Frame:
    """What the window draws of a state: its node positions (M, N, 3) (m) and speeds (M, N) (m/s), its readout,
    the sliders' config values in effect, and ``serial``, counting the frames handed over (a new one is new)."""

    serial: int
    points: np.ndarray
    speed: np.ndarray
    readout: Readout
    values: dict


class Producer:
    """The simulation side of the window: computes the frames of a :class:`Session` and hands the newest over.

    Frame k is the state at the first step boundary at or past ``k / fps`` s after the start (or the last reset).
    Commands (:meth:`submit`: a slider, pause, reset) are applied between two steps. :meth:`produce` computes the
    next frame in the calling thread; :meth:`start` runs it in a thread of its own (the interactive window),
    paced to real time when it is faster and :meth:`stop`\\ ped at a step boundary.

    Parameters
    ----------
    session : Session
        Stepped and changed only by this producer (the thread's, while it runs).
    fps : float
        Frames a simulated second.
    readout_every : float
        The readout's compatibility test at most this often (s of simulated time; :meth:`Session.readout`).
    knobs : sequence of Knob
        The config fields a frame reports (:attr:`Frame.values`).

    Attributes
    ----------
    cpu_steps : float
        CPU seconds (``time.process_time``, the whole process's) spent stepping so far.
    error : BaseException or None
        What stopped the thread, if anything but :meth:`stop` did.
    """

    def __init__(self, session: Session, fps: float = FPS, readout_every: float = READOUT_EVERY,
                 knobs=MACRO + MICRO):
        self.session, self.fps, self.readout_every = session, float(fps), float(readout_every)
        self.names = tuple(k.name for k in knobs)
        self.paused, self.cpu_steps, self.error = False, 0.0, None
        self._commands = collections.deque()  # appended by the window, taken by the producer (thread-safe ends)
        self._lock = threading.Lock()  # guards the hand-over of the newest frame
        self._wake, self._stop = threading.Event(), threading.Event()
        self._thread = None
        self._serial = 0
        self._origin, self._index = session.state.t, 0
        self._frame = None
        self._publish()

    # -- the hand-over -------------------------------------------------------------------
    @property
    def latest(self) -> Frame:
        """The newest frame (never waits for a step)."""
        with self._lock:
            return self._frame

    def _publish(self) -> None:
        s = self.session
        frame = Frame(serial=self._serial, points=np.array(s.points()), speed=s.speed(),
                      readout=s.readout(self.readout_every), values={name: s.value(name) for name in self.names})
        with self._lock:
            self._frame = frame
        self._serial += 1

    # -- commands ------------------------------------------------------------------------
    def submit(self, *command) -> None:
        """A command: ("set", name, value), ("pause", flag) or ("reset",). Applied by the thread between two steps
        while it runs, at once otherwise."""
        self._commands.append(command)
        if self.running:
            self._wake.set()
        else:
            self.apply()

    def apply(self) -> bool:
        """Apply the commands waiting (the caller is between two steps) and hand the state over; whether any was."""
        if not self._commands:
            return False
        while self._commands:
            kind, *args = self._commands.popleft()
            if kind == "set":
                name, value = args
                try:
                    self.session.set(**{name: value})
                except InputError as err:  # the frames' values say what is in effect
                    log.warning("deformable view: %s = %r refused: %s", name, value, err)
            elif kind == "pause":
                self.paused = bool(args[0])
            elif kind == "reset":
                self.session.reset()
                self._origin, self._index = self.session.state.t, 0
            else:
                raise ValueError(f"unknown command {kind!r}")
        self._publish()
        return True

    def _interrupted(self) -> bool:
        return bool(self._commands) or self._stop.is_set()

    # -- the frames ----------------------------------------------------------------------
    def produce(self) -> bool:
        """Compute the next frame (commands applied between steps) and hand it over; False, and no frame, when
        paused, stopped or the run has ended (diverged, stalled)."""
        while True:
            self.apply()
            if self._stop.is_set() or self.paused or self.session.status != "running":
                return False
            target = self._origin + (self._index + 1) / self.fps
            c0 = time.process_time()
            reached = self.session.advance_to(target, interrupt=self._interrupted)
            self.cpu_steps += time.process_time() - c0
            if reached:
                break
        self._index += 1
        self._publish()
        return True

    @property
    def running(self) -> bool:
        """Whether the thread runs."""
        return self._thread is not None and self._thread.is_alive()

    def start(self) -> None:
        """Run the frames in a thread of its own until :meth:`stop`."""
        self._stop.clear()
        self._thread = threading.Thread(target=self._loop, name="deformable-view-simulation", daemon=True)
        self._thread.start()

    def stop(self, timeout: float = 60.0) -> None:
        """Stop the thread at its next step boundary and wait for it (at most ``timeout`` s)."""
        self._stop.set()
        self._wake.set()
        if self._thread is not None:
            self._thread.join(timeout)
            if self._thread.is_alive():
                log.warning("deformable view: the simulation thread did not stop within %g s", timeout)

    def _loop(self) -> None:
        """The thread: frames as fast as they come, but not ahead of real time (frame k shown about k / fps s of
        wall time after the start; a late frame moves that clock on rather than hurrying the next ones)."""
        try:
            clock = (time.perf_counter(), self.session.state.t)
            while not self._stop.is_set():
                self._wake.clear()
                if self.produce():
                    ahead = clock[0] + (self.session.state.t - clock[1]) - time.perf_counter()
                    if ahead > 0:
                        self._wake.wait(ahead)  # early: wait for the frame's time (or a command)
                        continue
                else:  # paused, stopped or ended: wait for a command
                    self._wake.wait(0.5)
                clock = (time.perf_counter(), self.session.state.t)
        except Exception as err:  # noqa: BLE001 (shown in the window, raised again when it closes: Window.run)
            self.error = err
            self.session.status = f"failed ({type(err).__name__}: {err})"
            try:
                self._publish()
            except Exception:  # the state cannot be read: the window keeps its last frame
                log.debug("deformable view: no frame of the failed state", exc_info=True)


def _pyvista(offscreen: bool):
    pyvista = extra("pyvista", "render", "deformable view")
    if offscreen:
        from deformable.io.render import offscreen_pyvista

        return offscreen_pyvista()
    if not os.environ.get("DISPLAY"):
        raise InputError("deformable view: no display (DISPLAY is not set); run it under a desktop or xvfb-run, or "
                         "give --offscreen --frames N --screenshot FILE")
    return pyvista


#: the names of OpenGL renderers that draw on the CPU
SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swrast", "SwiftShader")


def software_renderer(plotter) -> bool:
    """Whether the plotter's OpenGL renderer draws on the CPU (:data:`SOFTWARE_RENDERERS`); False where it cannot
    tell."""
    try:
        report = plotter.render_window.ReportCapabilities()
    except (AttributeError, RuntimeError):
        return False
    return any(name in line for line in report.splitlines() if "renderer" in line.lower()
               for name in SOFTWARE_RENDERERS)


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
    size : (int, int)
        The window's size (pixels).
    readout_every : float
        The readout's compatibility test at most this often (s of simulated time).

    Attributes
    ----------
    cpu : dict
        CPU seconds (``time.process_time``) of the frames run in turn (:meth:`frame`): "steps", stepping, and
        "render", the rest of a frame (the readout, the mesh and text updates, rendering, a GIF frame).
    """

    def __init__(self, session: Session, offscreen: bool = False, fps: float = FPS, gif=None, size=(1100, 760),
                 readout_every: float = READOUT_EVERY):
        self.session, self.fps, self.recording, self.top = session, fps, False, 1.0
        self.producer = Producer(session, fps, readout_every)
        self.cpu = {"steps": 0.0, "render": 0.0}
        self._paused = False
        self.gif = str(gif or f"{session.config.scene}.gif")
        pv = self.pv = _pyvista(offscreen)
        self.plotter = pv.Plotter(off_screen=offscreen, window_size=size,
                                  title=f"deformable view {session.config.scene}")
        frame = self.producer.latest
        P = frame.points
        self.mesh = pv.StructuredGrid(P[..., 0], P[..., 1], P[..., 2])
        self.mesh["speed (m/s)"] = frame.speed.ravel(order="F")
        self.plotter.add_mesh(self.mesh, scalars="speed (m/s)", cmap="viridis", clim=(0.0, 1.0), smooth_shading=True,
                              scalar_bar_args=dict(title="speed (m/s)\n", vertical=True, position_x=0.9,
                                                   position_y=0.06, height=0.38, width=0.05, color="black",
                                                   n_labels=3, fmt="%.2g"))
        from deformable.io.render import camera, obstacle_mesh

        lo, hi = P.reshape(-1, 3).min(0), P.reshape(-1, 3).max(0)
        pad = 0.3 * float(np.max(hi - lo))
        for obstacle in session.model.scene.obstacles:
            self.plotter.add_mesh(obstacle_mesh(obstacle, np.array([lo, hi])), color="lightgrey", smooth_shading=True)
        self.plotter.camera_position = camera(np.array([lo - pad, hi + pad]))
        self.plotter.set_background("white")
        self.sliders, self._shown, self._requested, self._home = {}, dict(frame.values), dict(frame.values), {}
        for group, knobs, x0 in (("macro-control", MACRO, 0.02), ("micro-control", MICRO, 0.70)):
            self.plotter.add_text(group, position=(int(x0 * size[0]), int(0.84 * size[1])), font_size=10,
                                  color="black")
            for k, knob in enumerate(knobs):
                self._slider(knob, x0, 0.79 - 0.1 * k)
        self._fabric_menu(size)
        self.readout_text = self.plotter.add_text(frame.readout.text(), position="upper_left", font_size=9,
                                                  color="black", name="readout")
        self._drawn = frame.serial
        self.plotter.add_key_event("space", self.toggle_pause)
        self.plotter.add_key_event("r", self.reset)
        self.plotter.add_key_event("g", self.toggle_gif)

    def _slider(self, knob: Knob, x0: float, y: float) -> None:
        v0 = self.session.value(knob.name)
        if not v0 > 0:  # a zero weight (xi = 0): the slider starts from a small value instead
            v0 = {"xi": 1e-6, "eta": 1.0, "gamma": 0.01}.get(knob.name, 1.0)
        lo, hi = math.log10(v0 / knob.span), math.log10(v0 * knob.span)
        home = self._home[knob.name] = math.log10(max(self.session.value(knob.name), v0))

        def moved(value, knob=knob):
            if knob.name in self.sliders and not math.isclose(10.0**value, self._requested[knob.name], rel_tol=1e-9):
                self.set(knob.name, 10.0**value)  # (pyvista calls it once as the slider is made: nothing moved)

        w = self.plotter.add_slider_widget(moved, (lo, hi), value=home, title=self._title(knob, self._shown),
                                           pointa=(x0, y), pointb=(x0 + 0.26, y), style="modern",
                                           interaction_event="end", fmt=" ", title_height=0.018, title_color="black")
        self.sliders[knob.name] = (knob, w)

    #: the fabric menu's first entry: the scene's own material
    OWN = "scene's own"

    def _fabric_menu(self, size) -> None:
        """A menu of the named fabrics (a text slider, lower left): the scene's own material or a preset, whose
        density and warp and weft weights the running simulation takes (:meth:`Session._with_fabric`)."""
        names = self._fabric_names = [self.OWN, *dm.Fabric.presets()]
        self._fabric = self.session.config.fabric or self.OWN

        def chosen(name):
            if name != self._fabric:  # (pyvista calls it once as the widget is made: nothing chosen)
                self._fabric = name
                self.set("fabric", "" if name == self.OWN else name)

        self.plotter.add_text("fabric", position=(int(0.02 * size[0]), int(0.33 * size[1])), font_size=10,
                              color="black")
        self.fabric_menu = self.plotter.add_text_slider_widget(chosen, names, value=names.index(self._fabric),
                                                               pointa=(0.02, 0.28), pointb=(0.28, 0.28),
                                                               style="modern", interaction_event="end",
                                                               color="black")

    def choose(self, name: str) -> None:
        """Choose a fabric in the menu as a hand would (its widget's value, then its end-of-interaction event)."""
        import vtk

        self.fabric_menu.GetRepresentation().SetValue(self._fabric_names.index(name))
        self.fabric_menu.InvokeEvent(vtk.vtkCommand.EndInteractionEvent)

    @staticmethod
    def _title(knob: Knob, values: dict) -> str:
        """A slider's title: the value in effect; mu and gamma are f times their slider's value (section 3.1)."""
        value, f = values[knob.name], values.get("scale", 1.0)
        if knob.name in ("mu", "gamma") and f != 1:
            return f"{knob.label} = {f * value:.3g} (f x {value:.3g})"
        if knob.name == "scale":
            return f"{knob.label} = {value:.3g}: mu, gamma, forces"
        return f"{knob.label} = {value:.3g}"

    def set(self, name: str, value: float) -> None:
        """A slider moved: the running simulation takes ``value`` for the field ``name`` (at its next step
        boundary; the slider's title shows it once a frame computed with it is drawn)."""
        self._requested[name] = value
        self.producer.submit("set", name, value)

    def move(self, name: str, value: float) -> None:
        """Move a slider as a hand would (its widget's representation, then its end-of-interaction event)."""
        import vtk

        _, w = self.sliders[name]
        w.GetRepresentation().SetValue(math.log10(value))
        w.InvokeEvent(vtk.vtkCommand.EndInteractionEvent)

    @property
    def paused(self) -> bool:
        return self._paused

    def toggle_pause(self) -> None:
        self._paused = not self._paused
        self.producer.submit("pause", self._paused)

    def reset(self) -> None:
        """The scene's start and its own values (the sliders follow when the reset's frame is drawn)."""
        self.producer.submit("reset")
        if not self.producer.running:
            self.update()

    def toggle_gif(self) -> None:
        if self.recording:
            self.plotter.mwriter.close()
        else:
            self.plotter.open_gif(self.gif)
        self.recording = not self.recording

    def _sync(self, values: dict) -> None:
        """The sliders' titles (and, where moved by a reset, positions) to the values in effect."""
        if all(values[name] == self._shown[name] for name in self.sliders):
            return
        for name, (knob, w) in self.sliders.items():  # every title: f moves mu's and gamma's
            value = values[name]
            rep = w.GetRepresentation()
            if value != self._shown[name] and not math.isclose(10.0 ** rep.GetValue(), value, rel_tol=1e-9):
                rep.SetValue(math.log10(value) if value > 0 else self._home[name])
            rep.SetTitleText(self._title(knob, values))
        for name in self.sliders:
            if values[name] != self._shown[name]:
                self._shown[name] = self._requested[name] = values[name]

    def draw(self, frame: Frame) -> None:
        """Put ``frame`` in the scene (mesh, colours, readout, sliders); :meth:`show` renders it."""
        self.mesh.points = frame.points.reshape(-1, 3, order="F")
        self.mesh["speed (m/s)"] = frame.speed.ravel(order="F")
        top = float(frame.speed.max())
        if top > self.top:  # the colour range only grows (by doublings), so frames stay comparable
            self.top = 2.0 ** math.ceil(math.log2(top))
            self.plotter.update_scalar_bar_range((0.0, self.top))
        self.readout_text.SetText(2, frame.readout.text())  # the upper left corner of its vtkCornerAnnotation
        if frame.values != self._shown:
            self._sync(frame.values)
        self._drawn = frame.serial

    def update(self) -> None:
        """Draw the newest frame."""
        self.draw(self.producer.latest)

    def show(self) -> None:
        """Render what is drawn (and record it while ``g`` is on). On a software OpenGL renderer (Mesa's llvmpipe:
        no GPU) the window draws without multisampling: measured at 1100 x 760 pixels, a frame 55 ms of CPU with
        pyvista's default four samples against 12 ms without, the whole of a real-time budget (30 frames a second)."""
        if getattr(self.plotter, "_first_time", False):  # pyvista's render() draws only once the plotter is shown
            self.plotter.show(auto_close=False, interactive=False)  # (a window opens; off screen, its context)
            if software_renderer(self.plotter):
                self.plotter.disable_anti_aliasing()
        self.plotter.render()
        if self.recording:
            self.plotter.write_frame()

    def frame(self) -> None:
        """One frame in the calling thread: the simulation's next (1 / fps s on, unless paused), drawn and
        rendered; adds its CPU time to :attr:`cpu`."""
        c0, s0 = time.process_time(), self.producer.cpu_steps
        self.producer.produce()
        self.update()
        self.show()
        steps = self.producer.cpu_steps - s0
        self.cpu["steps"] += steps
        self.cpu["render"] += time.process_time() - c0 - steps

    def _events(self) -> None:
        """The window's loop until it closes: its events (keys, sliders, the camera, timers), the newest frame drawn
        when there is a new one, and a short sleep, twice a frame, in which the GIL is the simulation's. (VTK's own
        event loop, ``Start``, would hold the GIL while it waits, and the simulation thread would wait with it.)"""
        iren = self.plotter.iren
        while not iren.interactor.GetDone():  # q, e or the close button: TerminateApp sets it
            iren.process_events()  # (a RuntimeError, not a crash, where the window has no events: EGL's)
            self._tick()
            time.sleep(0.5 / self.fps)

    def _tick(self) -> None:
        """Draw the newest frame if there is a new one; never waits for the simulation."""
        frame = self.producer.latest
        if frame.serial != self._drawn:
            self.draw(frame)
            self.plotter.render()
            if self.recording:
                self.plotter.write_frame()

    def run(self, frames: int | None = None, screenshot=None, progress: str | None = None) -> float:
        """``frames`` frames in turn in this thread (None: the simulation in its own thread, drawn until the
        window closes), then ``screenshot`` (PNG) of the last; returns the wall time (s) the frames took.
        ``progress``: the name that starts a line on stderr each tenth of the ``frames`` (simulated time, an estimate
        of the time left from the second frame on: :class:`deformable.progress.Progress`)."""
        from deformable.progress import Progress, counted

        start = time.perf_counter()
        if frames is not None:
            bar = Progress(frames, progress or "view", enabled=bool(progress), warmup=True)
            for k in range(frames):
                self.frame()
                bar.update(k + 1, f"{k + 1} of {counted(frames, 'frame')}, t = {self.session.state.t:.3f} s")
            bar.close()
        else:
            if self.plotter.off_screen:
                raise InputError("deformable view: off screen, give the number of frames (--frames N)",
                                 field="--frames", value=None)
            self.producer.start()
            try:
                self.plotter.show(auto_close=False, interactive_update=True)  # the window opens; _events runs it
                if software_renderer(self.plotter):  # (:meth:`show`)
                    self.plotter.disable_anti_aliasing()
                self._events()
            finally:
                self.producer.stop()
            self.update()
        wall = time.perf_counter() - start
        if screenshot is not None:
            self.plotter.screenshot(str(screenshot))
        if self.recording:
            self.toggle_gif()
        self.plotter.close()
        if self.producer.error is not None:
            raise self.producer.error
        return wall
