r"""The peer rows of ``deformable bench`` (opt-in: ``--peers``): newton's VBD and Style3D cloth solvers on the hanging
cloth, in simulated seconds per CPU second.

The cloth is the project's ``hanging`` scene (:mod:`deformable.scenes.cloth`, its
parameters read from the scene's config): a 1 m x 1 m square of N x N particles
(``nodes`` a side, the node count of the project's FD grid), areal density
mu = 0.2 kg/m^2, starting horizontal (the plane z = 0 of newton's z-up world),
pinned at the two corners of one edge (mass 0, so inverse mass 0, and the
ACTIVE flag cleared: newton's way of fixing particles), falling under gravity
g = 9.81 m/s^2, with no ground, no obstacle and no self-contact (the project's
scene has none). It is built with newton's own grid helpers,
``ModelBuilder.add_cloth_grid`` (VBD) and ``newton.solvers.style3d.add_cloth_grid``
(Style3D), both a regular grid of right triangles (2 (N-1)^2 of them) with
bending elements on every interior edge. Every particle has the mass mu h^2,
h = L / (N - 1), as every node of the project's FD model has (its M = h1 h2
diag(mu), no control-area weights): 0.2064 kg in all on 64 x 64. (VBD's helper
gives each particle the mass passed to it; Style3D's lumps a third of each
triangle's area, which this bench overwrites with the same uniform mass.)

The parameters (eta = 50 N/m, xi = 1e-5 N m, gamma = 0.05 kg/(m^2 s), isotropic:
``shear`` = 1, so eta_ij = eta and xi_ij = xi for every i, j) are mapped onto
newton's by matching the small-strain and cylindrical-bending energies, since
the energies themselves differ from the project's eq. (13)
``W = sum_ij eta (G_ij - G0_ij)^2 + xi (B_ij - B0_ij)^2``. With the Green strain
E = (G - I) / 2 this stretching part is ``4 eta |E|^2`` (St Venant-Kirchhoff with
Lame mu = 4 eta and lambda = 0: Poisson ratio 0), and a cylinder of curvature
kappa stores ``xi kappa^2`` per unit area.

* VBD (stable Neo-Hookean membrane, ``tri_ke`` = Lame mu and ``tri_ka`` = Lame
  lambda per newton's kernel; dihedral-angle bending ``E = ke L (theta -
  theta0)^2 / 2`` per edge of rest length L): ``tri_ke = 4 eta = 200 N/m``,
  ``tri_ka = 0``, which linearise to the project's ``4 eta |eps|^2``; on this
  triangulation a cylinder puts theta = kappa h on the edges across it and nothing
  on the diagonals, ``ke h kappa^2 / 2`` per cell of area h^2 (h = L / (N - 1)),
  so ``edge_ke = 2 xi / h`` (1.26e-3 N on 64 x 64; it is mesh-dependent as the
  discrete dihedral energy is). Neo-Hookean is not St Venant-Kirchhoff at large
  strain, and the dihedral energy is not ``xi |B|^2`` in twist.
* Style3D (Baraff-Witkin stretching ``ku (|F_u| - 1)^2 / 2 + kv (|F_v| - 1)^2 / 2
  + ks (u.v)^2 / 2`` per area, u and v the unit columns of F; Bergou et al. 2006
  quadratic bending): ``tri_aniso_ke = (8 eta, 8 eta, 4 eta) = (400, 400, 200)
  N/m``, which linearise to ``4 eta (eps_11^2 + eps_22^2 + 2 eps_12^2)``; the
  quadratic bending on this grid stores ``1.5 k kappa^2`` per unit area for a
  cylinder along either axis (measured on the model's own rest data: 1.476 with
  the boundary at 64 x 64, 1.5 in the interior, independent of h), so every edge
  gets ``k = xi / 1.5``: ``edge_aniso_ke = (xi / 1.5, xi / 1.5, xi / 1.5 * 31 /
  32)``, as Style3D blends the three into ``a0 sin^12 + a1 cos^12 + 4 a2 sin^2
  cos^2`` of the edge's angle (the diagonals get a0 / 64 + a1 / 64 + a2). The
  quadratic model assumes an isometric (inextensible) bend and differs from
  ``xi |B|^2`` in twist as well.
* Damping: neither solver has the project's velocity damping ``-gamma v`` per unit
  area (VBD's ``tri_kd`` and ``edge_kd`` damp strain and angle rates, Style3D's
  ``tri_kd`` is unused), so it is applied as newton applies any external force:
  ``particle_f = -(gamma / mu) m v = -gamma h^2 v`` written by a small Warp kernel
  before every substep (the project's FD damping C = h1 h2 diag(gamma), taken
  explicitly at the substep's start velocity; both solvers add ``particle_f / m``
  to their inertial prediction). VBD's ``tri_kd`` and ``edge_kd`` are 0 (the project has no strain
  rate damping). Style3D also multiplies every velocity by 0.998 per substep
  (its ``update_velocity`` kernel), a decay of 0.24 1/s at its 1/120 s substep,
  about the project's gamma / mu = 0.25 1/s again: Style3D is damped about twice.

Each solver runs at the settings of newton's own hanging-cloth example
(``newton/examples/cloth/example_cloth_hanging.py``): frames of 1/60 s, VBD 10
substeps of 10 iterations, Style3D 2 substeps of 10 non-linear iterations (each of
10 PCG iterations, its ``Config`` default). These are fixed budgets: neither
solver has a convergence test, so a row says nothing about how far from the
implicit-Euler solution a substep ends (the matched-accuracy study,
:mod:`.accuracy`, measures that). The VBD example replays a frame as a
captured graph (Warp records one on the CPU too) and so does this bench (two
frames at a time where a frame has an odd number of substeps: the two states
swap at each substep, and a replay must leave them where it found them);
Style3D's host calls cannot be captured on the CPU, as its example says, so it
launches kernel by kernel. Self-contact (on in the example's VBD run) and Style3D's
collision handling are off: the project's scene has no contact.

Measured: ``compile_s``, the CPU seconds (``time.process_time``) of building the
model and solver, one warm-up frame and (VBD) the graph capture: the first run
compiles Warp's kernels (about 11 s VBD and 5 s Style3D on a cold kernel cache
here), later runs load them from Warp's kernel cache (0.3 to 3 s, mostly newton's
Python model building and VBD's graph colouring); then, from the initial state
again, ``cpu``, the CPU seconds of ceil(t_end / dt) frames, and ``wall``, their
wall-clock seconds; ``rate`` is the simulated time over ``cpu``. Warp runs on its
``cpu`` device, whose kernels run the threads of a launch serially on the calling
thread (Warp's CPU launch model; graph replay too): one thread, which the
table's threads column, cpu / wall, shows (0.87 to 1.00 when measured).

``drop`` is the pinned corners' height minus the lowest particle's (m) at the
end, so a broken setup shows. The cloth swings: the project's own ``hanging``
scene (FD, 32 x 32 nodes) drops 1.00 m at 0.5 s, swings up to 0.35 m at 1.0 s,
1.02 m at 1.4 s and is at 0.66 m at 2 s, so a drop at t_end between about 0.3 m
and 1.2 m is physical once the cloth has fallen; a row's status is "ok" only if
every position is finite and the drop is at least a quarter of min(g t^2 / 2, L)
and less than 3 L. A fixed budget shows in it too: at 64 x 64 Style3D's 10 PCG
iterations per non-linear iteration leave the cloth falling slower than free fall
(an unpinned cloth's centre is 0.154 m down after 0.2 s, against 0.196 m exact
and 0.201 m with 200 PCG iterations), so it creeps to the vertical and barely
swings.

One function builds the cloth and steps it, :func:`run_peer` (a solver, its
frame, substeps and iterations, the simulated time: the CPU seconds and the
final positions); the rows here run it at the example's budgets, the
matched-accuracy study (:mod:`.accuracy`) at many. newton and warp are imported
only inside the functions: without them every row says so in its status, with a
rate of nan.
"""

import contextlib
import dataclasses
import functools
import io
import math
import time
from dataclasses import dataclass

import numpy as np

from deformable import scenes
from validation.harness.report import markdown_table

__all__ = ["PEERS", "PeerRow", "PeerRun", "bench_peer", "bench_peers", "format_peers", "pinned", "run_peer"]

#: frames per second of newton's cloth examples (the frame length dt = 1 / FPS s)
FPS = 60

#: solver name -> (peer, substeps per frame, iterations per substep): newton's example_cloth_hanging.py settings
PEERS = {
    "vbd": ("newton VBD", 10, 10),
    "style3d": ("newton Style3D", 2, 10),
}

MISSING = "newton is not installed: pip install \".[peers]\" (newton and warp-lang)"

NOTE = {
    "vbd": "Neo-Hookean membrane + dihedral bending (energies differ from eq. 13); fixed budget: 10 substeps x 10 "
           "VBD iterations, no convergence test; gamma as an explicit external force; graph replay",
    "style3d": "Baraff-Witkin stretch + quadratic bending (energies differ from eq. 13); fixed budget: 2 substeps x 10 "
               "non-linear x 10 PCG iterations, no convergence test; gamma as an explicit external force, plus "
               "Style3D's own 0.998 velocity factor per substep",
}


@dataclass(frozen=True)
class PeerRow:
    """One peer line: a newton cloth solver on the hanging cloth; times in seconds, lengths in m."""

    peer: str
    solver: str
    nodes: str
    particles: int
    dt: float
    substeps: int
    iterations: int
    t_end: float
    steps: int
    cpu: float
    wall: float
    rate: float
    compile_s: float
    drop: float
    status: str
    note: str


def _missing() -> bool:
    """newton or warp cannot be imported."""
    try:
        import newton  # noqa: F401
        import warp  # noqa: F401
    except ImportError:
        return True
    return False


@functools.cache
def _damping_kernel():
    """The Warp kernel writing the project's velocity damping as an external force, ``f = -c m v`` (c in 1/s)."""
    import warp as wp

    @wp.kernel
    def velocity_damping(qd: wp.array(dtype=wp.vec3), mass: wp.array(dtype=float), c: float,
                         f: wp.array(dtype=wp.vec3)):
        i = wp.tid()
        f[i] = -c * mass[i] * qd[i]

    return velocity_damping


def _build(solver: str, n: int, cfg, iterations: int, linear_iterations: int = 10):
    """(model, solver) of the hanging cloth on n x n particles for one newton solver:
    ``iterations`` VBD iterations, or Style3D non-linear iterations of ``linear_iterations`` PCG iterations each,
    per substep."""
    import newton
    import warp as wp
    from newton.solvers import style3d

    size = float(cfg.size[0])
    h = size / (n - 1)
    builder = newton.ModelBuilder()
    grid = {"pos": wp.vec3(0.0, 0.0, 0.0), "rot": wp.quat_identity(), "vel": wp.vec3(0.0, 0.0, 0.0),
            "dim_x": n - 1, "dim_y": n - 1, "cell_x": h, "cell_y": h, "mass": cfg.scale * cfg.mu * h * h}
    if solver == "style3d":
        newton.solvers.SolverStyle3D.register_custom_attributes(builder)
        k = cfg.xi / 1.5
        style3d.add_cloth_grid(builder, **grid, tri_aniso_ke=wp.vec3(8 * cfg.eta, 8 * cfg.eta, 4 * cfg.eta), tri_ka=0.0,
                               tri_kd=0.0, edge_aniso_ke=wp.vec3(k, k, k * 31 / 32), edge_kd=0.0)
    else:
        builder.add_cloth_grid(**grid, tri_ke=4 * cfg.eta, tri_ka=0.0, tri_kd=0.0, edge_ke=2 * cfg.xi / h, edge_kd=0.0)
    builder.particle_mass[:] = [grid["mass"]] * n * n
    for p in pinned(n):
        builder.particle_mass[p] = 0.0
        builder.particle_flags[p] = builder.particle_flags[p] & ~newton.ParticleFlags.ACTIVE
    if solver == "vbd":
        builder.color(include_bending=True)
    model = builder.finalize(device="cpu")
    model.set_gravity((0.0, 0.0, -cfg.g))
    if solver == "style3d":
        config = newton.solvers.SolverStyle3D.Config(iterations=iterations, linear_iterations=linear_iterations)
        sim = newton.solvers.SolverStyle3D(model=model, config=config)
        sim.collision = None
    else:
        sim = newton.solvers.SolverVBD(model=model, iterations=iterations)
    return model, sim


def pinned(n: int) -> list[int]:
    """The pinned particles of the n x n cloth: the two corners of its last row (newton's grid helpers number the
    particles row by row)."""
    return [(n - 1) * n, n * n - 1]


@dataclass(frozen=True)
class PeerRun:
    """What one run of a newton solver on the hanging cloth measured: CPU and wall seconds of the timed frames,
    the CPU seconds before them (``compile_s``), the substeps taken and the final positions (m)."""

    solver: str
    frame_dt: float  # s
    substeps: int  # substeps per frame
    iterations: int  # VBD iterations, or Style3D non-linear iterations, per substep
    linear_iterations: int  # Style3D's PCG iterations per non-linear iteration (VBD: 0)
    frames: int
    cpu: float  # s
    wall: float  # s
    compile_s: float  # s
    q: np.ndarray | None  # final particle positions (particles, 3), m; None unless the run ended
    status: str  # "ran", or why not (MISSING, a failure)

    @property
    def t_end(self) -> float:
        """The simulated time (s): whole frames."""
        return self.frames * self.frame_dt

    @property
    def steps(self) -> int:
        """Substeps taken (0 unless the run ended)."""
        return self.frames * self.substeps if self.q is not None else 0


def run_peer(solver: str, nodes: int = 64, frame_dt: float = 1.0 / FPS, substeps: int = 1, iterations: int = 10,
             t_end: float = 2.0, linear_iterations: int = 10) -> PeerRun:
    """Run one newton solver ("vbd" or "style3d") on the hanging cloth of nodes x nodes particles, in this process.

    Builds the model and solver, runs one warm-up frame (and, VBD, captures a graph), then runs ceil(t_end /
    frame_dt) frames from the initial state again, timed (module docstring).

    Parameters
    ----------
    solver : str
        "vbd" or "style3d".
    nodes : int
        Particles a side.
    frame_dt : float
        The frame (s); a substep is frame_dt / substeps.
    substeps : int
        Substeps per frame.
    iterations : int
        VBD iterations, or Style3D non-linear iterations, per substep.
    t_end : float
        Simulated time (s), rounded up to whole frames.
    linear_iterations : int
        Style3D's PCG iterations per non-linear iteration (ignored by VBD).

    Returns
    -------
    PeerRun
        Times in CPU and wall seconds, the final positions (m); its status says MISSING without newton or warp,
        the exception if the run failed.
    """
    frames = math.ceil(t_end / frame_dt - 1e-9)
    linear = linear_iterations if solver == "style3d" else 0
    planned = PeerRun(solver, frame_dt, substeps, iterations, linear, frames, math.nan, math.nan, math.nan, None, "")
    if _missing():
        return dataclasses.replace(planned, status=MISSING)
    import warp as wp

    cfg = scenes.config("hanging", nodes=(nodes, nodes))
    log_level = wp.config.log_level
    wp.config.log_level = wp.LOG_WARNING
    try:
        with wp.ScopedDevice("cpu"), contextlib.redirect_stdout(io.StringIO()):
            measured = _measure(planned, nodes, cfg)
    except Exception as e:  # noqa: BLE001 - a failing peer is a row, not a failed bench
        return dataclasses.replace(planned, status=f"failed: {type(e).__name__}: {' '.join(str(e).split())[:160]}")
    finally:
        wp.config.log_level = log_level
    return dataclasses.replace(planned, status="ran", **measured)


def _measure(run: PeerRun, nodes: int, cfg) -> dict:
    """The timed part of :func:`run_peer` on Warp's current device: build, warm up (VBD: capture a graph), then
    ``run.frames`` frames from the initial state again; its cpu, wall, compile_s (s) and final positions q (m)."""
    import warp as wp

    c0 = time.process_time()
    model, sim = _build(run.solver, nodes, cfg, run.iterations, run.linear_iterations)
    s0, s1 = model.state(), model.state()
    kernel, c = _damping_kernel(), cfg.gamma / cfg.mu
    h = run.frame_dt / run.substeps

    def frame():
        nonlocal s0, s1
        for _ in range(run.substeps):
            wp.launch(kernel, dim=model.particle_count, inputs=[s0.particle_qd, model.particle_mass, c],
                      outputs=[s0.particle_f])
            sim.step(s0, s1, None, None, h)
            s0, s1 = s1, s0

    frame()
    # a graph replays whole frames and must leave the states where it found them: an even number of
    # substeps (the states swap at each), so one frame, or two of an odd number of substeps
    block = 1 if run.substeps % 2 == 0 else 2
    graph = None
    if run.solver == "vbd":
        with wp.ScopedCapture() as capture:
            for _ in range(block):
                frame()
        graph = capture.graph
    wp.synchronize()
    compile_s = time.process_time() - c0
    for s in (s0, s1):
        s.particle_q.assign(model.particle_q)
        s.particle_qd.assign(model.particle_qd)
    w0, c0 = time.perf_counter(), time.process_time()
    replays, rest = divmod(run.frames, block) if graph is not None else (0, run.frames)
    for _ in range(replays):
        wp.capture_launch(graph)
    for _ in range(rest):
        frame()
    wp.synchronize()
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    return {"cpu": cpu, "wall": wall, "compile_s": compile_s, "q": s0.particle_q.numpy().astype(float)}


def bench_peer(solver: str, nodes: int = 64, t_end: float = 2.0) -> PeerRow:
    """One newton solver ("vbd" or "style3d") on the hanging cloth of nodes x nodes particles for t_end seconds, at
    newton's example settings (:data:`PEERS`)."""
    peer, substeps, iterations = PEERS[solver]
    r = run_peer(solver, nodes, 1.0 / FPS, substeps, iterations, t_end)
    cfg = scenes.config("hanging", nodes=(nodes, nodes))
    q, drop = r.q, math.nan
    if q is None:
        status = r.status
    elif not np.isfinite(q).all():
        status = "non-finite positions"
    else:
        drop = float(q[pinned(nodes), 2].mean() - q[:, 2].min())
        expected = min(0.5 * cfg.g * r.t_end ** 2, float(cfg.size[1]))
        if not 0.25 * expected <= drop < 3 * float(cfg.size[1]):
            status = f"suspect: drop {drop:.3g} m after {r.t_end:g} s (expected about {expected:.3g} m)"
        else:
            status = "ok"
    rate = r.t_end / r.cpu if r.steps and r.cpu > 0 else math.nan
    return PeerRow(peer, solver, f"{nodes}x{nodes}", nodes * nodes, r.frame_dt, substeps, iterations, t_end, r.steps,
                   r.cpu, r.wall, rate, r.compile_s, drop, status, NOTE[solver])


def bench_peers(nodes: int = 64, t_end: float = 2.0, solvers=("vbd", "style3d")) -> list[PeerRow]:
    """The peer rows: each newton solver of ``solvers`` on the hanging cloth of nodes x nodes particles for t_end s."""
    return [bench_peer(s, nodes, t_end) for s in solvers]


def format_peers(rows) -> str:
    """A markdown table of peer rows."""
    return markdown_table(
        ("peer", "nodes", "particles", "frame dt (ms)", "substeps x iterations", "t end (s)", "steps", "CPU (s)",
         "threads", "sim s / CPU s", "compile (s)", "drop (m)", "status", "note"),
        [(r.peer, r.nodes, r.particles, f"{1e3 * r.dt:.4g}", f"{r.substeps} x {r.iterations}", f"{r.t_end:g}", r.steps,
          f"{r.cpu:.2f}", f"{r.cpu / r.wall:.2f}" if r.wall > 0 else "", f"{r.rate:.3g}", f"{r.compile_s:.1f}",
          f"{r.drop:.3f}", r.status, r.note) for r in rows])
