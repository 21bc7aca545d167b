r"""A run of a scene as one object: config, backend and output folder; its model, stepper, run, resume, checkpoints.

::

    from deformable import Simulation, scenes

    sim = Simulation(scenes.config("hanging"), backend="fe")     # the grid, model and step a run takes
    result = sim.run(t_end=0.5)                                  # a RunResult; sim.model, sim.stepper
    sim = Simulation("curtain", out="runs/curtain")             # with an output folder: series, config, checkpoints
    sim.run(t_end=1.0, every=0.02, checkpoint_every=50)
    Simulation("curtain", out="runs/curtain").resume("runs/curtain/curtain-checkpoint-000050.npz").run(t_end=2.0)

The path from a config to a run is written here once, for the command line's ``run``, ``view`` and ``sweep``,
the benches, the studies and a user's script:

- **Grid.** ``nodes`` (M, N) where the caller set it; else the scene's grid, written in FD's nodes, taken in the
  backend's own unit (:meth:`deformable.backends.Discretisation.scene_nodes`: FE half as many elements a side).
- **Backend.** By name, through the registry (:meth:`Discretisation.lookup`), which loads installed backends
  from their entry points (group ``deformable.backends``): the core imports none.
- **Step.** ``dt`` where the caller set it; else the scene's, or half the backend's stretching bound where
  that is smaller (:func:`deformable.dynamics.dt.within_stable`, the one rule).

Before anything is written, :meth:`Simulation.prepare` checks all of a run (its length, a start clear of the
obstacles, the output folder, the series' size on disk); :meth:`Simulation.run` prepares where the caller did
not, then steps (eq. (22)-(27), :class:`deformable.TimeStepper`). With an output folder it writes, as the run goes:
``<scene>.toml`` (the resolved config and a ``[run]`` table: backend, scheme, steps, frame interval, version; a
run of that file is the same run bit for bit), ``<scene>.xdmf`` (frames on the requested times,
:class:`deformable.io.XDMFWriter`), ``<scene>-checkpoint-*.npz`` and, if the run diverges, ``<scene>-diverged.npz``
(the last good state). :meth:`Simulation.resume` continues from a checkpoint bit for bit, its series included.
"""

from __future__ import annotations

import logging
import math
import shutil
from pathlib import Path

import ipctk

from .. import scenes
from ..backends.registry import Discretisation
from ..checks import installed_version
from ..contact.clearance import clearance, require_clear
from ..dynamics import Callback, EnergyMonitor, State, TimeStepper
from ..dynamics.dt import within_stable
from ..errors import InputError
from ..io import CheckpointWriter, XDMFWriter, frame_time, load_checkpoint, save_checkpoint
from ..io.folder import RunFolder, write_text
from ..io.series import continuation
from ..scene.scene import Scene
from ..limits import check_series
from .resume import abandon, fits, owns

__all__ = ["Simulation", "DEFAULT_EVERY"]

log = logging.getLogger(__name__)

#: the frame interval (s of simulated time) of a run with an output folder, by default
DEFAULT_EVERY = 0.02


class Simulation:
    """A scene config run on a backend (module docstring).

    Parameters
    ----------
    config : SceneConfig, a scene name or a TOML scene file (``*.toml``); or a :class:`deformable.Scene` built by
        hand, which runs as it is (its grid; ``dt`` required, s or "auto"; no output folder, no resume: a Scene
        has no file form: give ``trackers``, e.g. a :class:`deformable.XDMFWriter`, to :meth:`run`)
    backend : str or None
        A registered backend's name (FD's and FE's, or an installed one's); None: the first
        (:meth:`Discretisation.names`, the paper's finite differences).
    out : path or None
        The output folder (None: nothing is written); a folder holding another run's results is refused unless
        ``overwrite``.
    nodes : (M, N) or None
        The node grid, or None for the scene's grid in the backend's unit.
    dt : float or None
        The step (s), or None for the scene's within the backend's stable step.
    scheme : str or None
        The time-stepping scheme (:data:`deformable.SCHEMES`), or None for the force model's default.
    stepping : dict or None
        More arguments of the :class:`deformable.TimeStepper` (``newton``, ``solver``, ``dt_min``).
    options
        Go to the backend's model (e.g. FD ``weighting``, FE ``element``).

    Attributes
    ----------
    config : the scene config with the grid and step the run takes (None for a Scene built by hand)
    asked : the config (or Scene) as given, before the grid and step were taken
    dt : the step (s) the run takes (or "auto")
    scene, model : the :class:`deformable.Scene` and the backend's model of it
    backend : str; ``descriptor`` its :class:`~deformable.backends.Discretisation`
    X0 : (ndof, 3) the constraints' reference positions (m): the initial state, or a checkpoint's
    start : State or None, the state a resumed run continues from
    result : the last run's :class:`deformable.RunResult` (None before); ``series`` its XDMFWriter,
        ``energy`` its EnergyMonitor, ``checkpoints`` the files written, ``clearances`` the clearance after each
        step (m, with obstacles and an output folder)
    """

    def __init__(self, config, backend: str | None = None, out=None, *, nodes=None, dt=None, scheme: str | None = None,
                 stepping: dict | None = None, overwrite: bool = False, **options):
        if isinstance(config, (str, Path)):
            config = scenes.read_toml(config) if str(config).endswith(".toml") else scenes.config(str(config))
        backend = Discretisation.names()[0] if backend is None else backend
        self.descriptor = Discretisation.lookup(backend)
        self.backend, self.asked = backend, config
        if isinstance(config, Scene):
            self._by_hand(config, nodes, dt, out)
            self.scene, self.config, self.dt = config, None, dt
            self.model = self.descriptor.build(self.scene, **options)
        elif isinstance(config, scenes.SceneConfig):
            config = config.replace(nodes=tuple(int(n) for n in nodes) if nodes is not None
                                    else self.descriptor.scene_nodes(config.nodes))
            self.scene = scenes.build(config)
            self.model = self.descriptor.build(self.scene, **options)
            step = dt if dt is not None else within_stable(self.model, config.dt)
            self.config = config if step == config.dt else config.replace(dt=step)
            self.dt = self.config.dt
        else:
            raise InputError(f"Simulation needs a scene config, a scene's name or a Scene, got {config!r}",
                             field="config", value=config)
        self.out = None if out is None else Path(out)
        self.overwrite, self.scheme, self.stepping = overwrite, scheme, dict(stepping or {})
        self.X0, self.start, self.checkpoint = self.model.initial_state(), None, None
        self.result = self.series = self.energy = None
        self.checkpoints, self.clearances = [], []
        self._stepper = self._plan = None

    @staticmethod
    def _by_hand(scene, nodes, dt, out) -> None:
        """InputError for what a Scene built by hand cannot take: a grid (it has its own), no step, a folder."""
        if nodes is not None:
            raise InputError("nodes: a Scene runs on its own grid (Sheet(nodes=...))", field="nodes", value=nodes)
        if dt is None:
            raise InputError("dt: a Scene built by hand has no step of its own; give dt (s, or 'auto')", field="dt",
                             value=dt)
        if out is not None:
            raise InputError("out: a run written to a folder needs a scene config (its resolved file); a Scene "
                             "built by hand has none: give run() a tracker, e.g. deformable.XDMFWriter", field="out",
                             value=out)

    def __repr__(self) -> str:
        M, N = self.scene.sheet.nodes
        name = self.config.scene if self.config is not None else self.scene.name or "a scene"
        return f"Simulation({name!r}, backend={self.backend!r}, nodes={M}x{N}, dt={self.stepper.dt:g})"

    @property
    def stepper(self) -> TimeStepper:
        """The run's :class:`deformable.TimeStepper` (built on first use)."""
        if self._stepper is None:
            self._stepper = TimeStepper(self.model, self.dt, scheme=self.scheme, **self.stepping)
        return self._stepper

    # -- resume ---------------------------------------------------------------------
    def resume(self, path, checkpoint: dict | None = None) -> Simulation:
        """Continue from the checkpoint file ``path`` (``checkpoint``: its contents, where already loaded): bit
        for bit the uninterrupted run, the controller's adapted step included. InputError naming the first field
        in which the checkpoint's run differs from this one. Returns self."""
        if self.config is None:
            raise InputError("resume: a Scene built by hand has no file form to check a checkpoint against; resume "
                             "a run of a scene config, or give TimeStepper.run its state", field="resume", value=path)
        ck = checkpoint if checkpoint is not None else load_checkpoint(path, t0=0.0)
        fits(path, ck, self.config, self.backend, self.stepper)
        if ck["memory"] is not None:  # the adapted step and the rest of the controller's memory
            try:
                self.stepper.restore(ck["memory"])
            except InputError as err:
                raise InputError(f"resume file {str(path)!r}: {err}", field="resume", value=path) from None
        elif self.stepper.adaptive:
            log.warning("%s holds no controller memory (an earlier version wrote it): the resumed run starts at "
                        "dt = %g s and differs from the uninterrupted one wherever its step adapted", path,
                        self.config.dt)
        self.X0 = ck["X0"]
        self.start = State(t=ck["t"], X=ck["X"], V=ck["V"], step=ck["step"], A=ck["A"])
        self.checkpoint = Path(path)
        return self

    # -- prepare and run ------------------------------------------------------------
    def prepare(self, *, t_end: float | None = None, steps: int | None = None, every: float | None = None,
                checkpoint_every: int | None = None, compress: bool | None = None) -> Simulation:
        """Check all of a run before anything is written; InputError (or ResourceError) on what cannot run.

        ``steps`` is the step number to stop at (a resumed run stops where the uninterrupted one does), or
        ``t_end`` the time (s), exactly; neither: the config's t_end. ``every`` is the frame interval (s; an output
        folder's default :data:`DEFAULT_EVERY`), ``checkpoint_every`` a checkpoint every K steps, ``compress`` the
        series' gzip (None: above 32 x 32 nodes). Returns self.
        """
        t_now, step_now = (0.0, 0) if self.start is None else (self.start.t, self.start.step)
        if self.scene.obstacles:  # a start inside an obstacle cannot be stepped
            try:
                require_clear(self.model, self.X0 if self.start is None else self.start.X, "the start", t_now)
            except ValueError as err:
                raise InputError(str(err)) from None
        config = self.config
        if steps is not None:
            if steps <= step_now:
                raise InputError(f"the run already stands at step {step_now} (t = {t_now:.6g} s); nothing to do "
                                 f"until step {steps}", field="--steps", value=steps)
            left, end = steps - step_now, None
            if config is not None:
                config = config.replace(t_end=frame_time(steps * config.dt))
        else:
            if t_end is None and config is None:
                raise InputError("t_end: a Scene built by hand has no end time of its own; give t_end or steps",
                                 field="t_end", value=None)
            end = t_end if t_end is not None else config.t_end
            if not end > t_now * (1 + 1e-12):
                raise InputError(f"the run already stands at t = {t_now:.6g} s (step {step_now}); nothing to do "
                                 f"until t = {end:.6g} s", field="--t-end", value=end)
            left = None
            if config is not None:
                config = config.replace(t_end=end)
        self.stepper.length(t_now, steps=left, t_end=end)  # a bad length or one beyond the cap, before any work
        every = every if every is not None or self.out is None else DEFAULT_EVERY
        if checkpoint_every or self.start is not None:
            # a run that checkpoints or resumes is resumed bit for bit: the IPC Toolkit's sums over the contact
            # pairs run in a varying order on more than one thread and move the last digits (docs/design.md,
            # "Checkpoints")
            ipctk.set_num_threads(1)
        self.config = config
        self._plan = dict(steps=left, t_end=end, every=every, checkpoint_every=checkpoint_every, compress=compress,
                          settings=dict(backend=self.backend, scheme=self.stepper.scheme, steps=steps, every=every,
                                        version=installed_version()))
        if self.out is not None:
            self._claim(t_now)
        return self

    def _claim(self, t_now: float) -> None:
        """The output folder, checked (not yet claimed), and the series a resumed run continues."""
        plan, self._continued = self._plan, None
        if self.checkpoint is not None:
            home = self.checkpoint.resolve().parent
            source = home / f"{self.config.scene}.xdmf"
            own = lambda folder: owns(folder, self.config, self.backend)  # noqa: E731
            if source.is_file() and own(home):
                self._continued = source
                continuation(source, self.start.step, self.start.t, plan["every"])  # a series with a hole: refused
            elif source.is_file():
                log.warning("the series %s is not this run's (its config differs): the resumed run starts a new "
                            "series", source)
            self._folder = RunFolder(self.out, overwrite=self.overwrite, own=own)
        else:
            self._folder = RunFolder(self.out, overwrite=self.overwrite)
        self._folder.check()
        self.out = self._folder.path
        span = (plan["t_end"] - t_now) if plan["t_end"] is not None else plan["steps"] * self.config.dt
        if plan["every"]:
            check_series(self.out / f"{self.config.scene}.xdmf", self.config.nodes,
                         int(math.ceil(span / plan["every"])) + 2)

    def run(self, *, trackers=(), progress: bool | str = False, **length):
        """Run (``length``: the arguments of :meth:`prepare`, which runs first where they are given or the run is
        not prepared); returns the :class:`deformable.RunResult`. ``trackers`` watch the run besides the output's
        own; ``progress`` True (or a name to start its lines with) prints progress."""
        if length or self._plan is None:
            self.prepare(**length)
        plan = self._plan
        if progress is True:
            progress = self.config.scene if self.config is not None else self.scene.name
        if self.out is None:
            self.result = self.stepper.run(self.X0, steps=plan["steps"], t_end=plan["t_end"], trackers=list(trackers),
                                           progress=progress, resume=self.start)
            return self.result
        with self._folder:
            self.result = self._run_into_folder(plan, list(trackers), progress)
        return self.result

    def _run_into_folder(self, plan, trackers, progress):
        cfg, out = self.config, self.out
        config_text = scenes.to_toml(cfg, plan["settings"])
        write_text(out / f"{cfg.scene}.toml", config_text)
        meta = dict(scene=cfg.scene, config=config_text, backend=self.backend, dt=cfg.dt, nodes=cfg.nodes)
        path = out / f"{cfg.scene}.xdmf"
        if self._continued is not None and self._continued.resolve() != path.resolve():
            for src in (self._continued, self._continued.with_suffix(".h5")):
                shutil.copyfile(src, out / src.name)
        if self.start is not None:
            abandon(out, cfg.scene, self.start.step)
        self.series = XDMFWriter(path, interval=plan["every"], reference=self.X0, append=self.start is not None,
                                 compress=plan["compress"])
        self.energy = EnergyMonitor(every=max(1, int(round(plan["every"] / cfg.dt))))
        trackers += [self.series, self.energy]
        self.clearances = []
        if self.scene.obstacles:
            trackers.append(Callback(lambda s: self.clearances.append(clearance(self.model, s.X, t=s.t))))
        ckpt = None
        if plan["checkpoint_every"]:
            ckpt = CheckpointWriter(out, f"{cfg.scene}-checkpoint", plan["checkpoint_every"], self.X0, **meta)
            trackers.append(ckpt)
        try:
            result = self.stepper.run(self.X0, steps=plan["steps"], t_end=plan["t_end"], trackers=trackers,
                                      progress=progress, resume=self.start)
        finally:
            self.series.close()
        self.checkpoints = list(ckpt.written) if ckpt else []
        if result.status == "diverged":
            self.checkpoints.append(save_checkpoint(out / f"{cfg.scene}-diverged.npz", result.state, self.X0,
                                                    memory=self.stepper.memory(), **meta))
        return result
