r"""A scene's parameters as the paper groups them, in SI units: what a person sets, and what it does.

The paper's interface has two functionally independent sets (section 3.1; section 4 on units):
*macro-control*, the mass density mu, the damping density gamma and the applied forces f, which the
section 3.1 factor ``scale`` multiplies together; and *micro-control*, the weights eta_ij, xi_ij of the
energy (13), the sheet's resistance to stretching and to bending. :func:`parameters` reads both off a
scene's config and its model and adds what they imply:

- what ``scale`` did (:meth:`~deformable.scenes.SceneConfig.scaling`): by eq. (11) divided by the scale, a
  scaled sheet moves as the real one would with eta / scale and xi / scale;
- the linear material the weights make: about a flat rest state the energy's stretching stiffness is
  E h = 2 s_eta eta and its bending rigidity D = s_xi xi, with (s_eta, s_xi) the force model's
  :attr:`~deformable.physics.ForceModel.stiffness` ((4, 2) for the variational model: Koiter's energy at
  nu = 0 gives eta = E h / 8 and xi = E h^3 / 24; (1, 1) for the paper's force (14));
- the stable step of the paper's semi-implicit scheme (eqs. (22)-(27)) with these mu and eta: lagging
  alpha (eq. (25)) bounds it by about h sqrt(mu / (2 eta G)) on FD (the backend's ``stable_step``);
- the bending length c = (D / (mu g))^(1/3) of Peirce's cantilever test (Peirce 1930, J. Textile Inst. 21,
  T377; ASTM D1388), what a textile lab measures, and the folds' length scale l_f = (D H / (mu g))^(1/4)
  (:func:`~deformable.scenes.fold_wavelength`; Cerda and Mahadevan 2003, Phys. Rev. Lett. 90, 074302), which
  sets the width of a hanging sheet's folds. Both with the simulated mu g (scaled), so with the real-world
  values when D is read as D / scale.

Whether a grid resolves the folds is judged by what the paper study measures
(validation/studies/paper/folds.py): the *narrowest* fold, the shortest distance in a1 between consecutive
extrema of the out-of-plane displacement along a row, over the rows and the snapshots of the last 0.4 s (not the
median). The folds are resolved when the narrowest is at least :data:`RESOLVED` = 3 grid spacings h. The
prediction: the narrowest fold is at least :data:`NARROWEST_PER_FOLD_SCALE` = 2/3 of l_f, so the folds are
resolved when l_f spans at least RESOLVED / NARROWEST_PER_FOLD_SCALE = :data:`FOLD_SCALE_SPACINGS` = 4.5 grid
spacings. Measured on the drawn curtain (FD, the variational model with its self-contact, its 2 s, one thread):
l_f / h, then the narrowest late fold in h and in cm, then CPU s (plain: the curtain before it was shipped in
denim, ``fabric="" mu=0.2 eta=20 xi=1e-4 shear=1``; xi = 1e-5 with it),

===================  ===================  ====================  ====================  ====================
run                  32 x 32 nodes        48 x 48               64 x 64               80 x 80
===================  ===================  ====================  ====================  ====================
xi = 1e-4 (plain)    3.26: 6 h 19 cm 26   4.94: 5 h 11 cm 48    6.63: 12 h 19 cm 69
xi = 1e-5            1.83: 2 h 6.5 cm 19  2.78: 1 h 2.1 cm 68                         4.67: 5 h 6.3 cm 339
denim                2.41: 3 h 9.7 cm 38  3.66: 4 h 8.5 cm 116  4.90: 5 h 7.9 cm 185
tablecloth           2.29: 4 h 13 cm 42   3.48: 1 h 2.1 cm 116  4.66: 8 h 13 cm 260
jacket-polyester     2.12: 3 h 9.7 cm 37  3.22: 4 h 8.5 cm 97   4.32: 1 h 1.6 cm 196  5.41: 9 h 11 cm 334
tshirt-knit          1.71: 2 h 6.5 cm 31  2.60: 2 h 4.3 cm 75   3.48: 2 h 3.2 cm 154
===================  ===================  ====================  ====================  ====================

Every run with l_f >= 4.66 h had its narrowest fold at least 5 h wide (1.0 to 1.8 l_f). Below, runs fold at 1
or 2 h up to l_f = 4.32 h (jacket-polyester on 64 x 64: a one-node kink in a ridge under the rod while the end
is drawn, gone 0.1 s after), and the same fabric one grid coarser need not (tablecloth: 4 h on 32, 1 h on 48,
8 h on 64): the narrowest fold is not a smooth function of l_f / h, nor does it converge in metres with
refinement for every run (xi = 1e-4: 19, 11, 19 cm), so the ratio narrowest / l_f of the runs that look
converged (1.0: denim, xi = 1e-4) does not predict it; its rule l_f >= 3 h would call tablecloth on 48 and
jacket-polyester on 64 resolved. The rule here is a threshold placed above the largest l_f / h of a grid-scale
run (4.32), not a fitted law: it holds for the 19 runs measured, conservatively below it (6 of the 13 runs
below 4.5 h kept 3 h or more). On FD the narrowest fold is a whole number of spacings (the extrema of a node
polyline sit at nodes). FE was not measured for it (its narrowest fold on the plain curtain, 3.75 h on 32 x 32
elements, is wider in metres than FD's on 64 x 64); the flag and the other scenes are judged by the curtain's
rule.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..physics.force_models import ForceModel

__all__ = ["RESOLVED", "FOLD_SCALE_SPACINGS", "NARROWEST_PER_FOLD_SCALE", "Parameter", "Parameters",
           "parameters", "fold_scale", "resolving_nodes"]

#: the narrowest fold a grid resolves, in grid spacings (the paper study's NARROWEST,
#: validation/studies/paper/folds.py)
RESOLVED = 3.0
#: grid spacings the folds' length scale l_f = (D H / (mu g))^(1/4) (Cerda and Mahadevan 2003) must span for the
#: narrowest fold to be at least RESOLVED spacings wide. Measured on the drawn curtain (module docstring's table):
#: every run with l_f >= 4.66 h had its narrowest fold at least 5 h wide; runs at l_f = 2.8, 3.5 and 4.3 h folded
#: at 1 h (xi = 1e-5 on FD 48, tablecloth on 48, jacket-polyester on 64). 4.5: above the largest grid-scale run's
#: 4.32 and below the smallest resolved one's 4.66
FOLD_SCALE_SPACINGS = 4.5
#: the narrowest fold predicted, a fraction of l_f: RESOLVED / FOLD_SCALE_SPACINGS, a lower bound where l_f spans
#: FOLD_SCALE_SPACINGS (there the measured narrowest was 1.0 to 1.8 l_f), not a fit
NARROWEST_PER_FOLD_SCALE = RESOLVED / FOLD_SCALE_SPACINGS


@dataclass(frozen=True)
class Parameter:
    """One parameter: ``real`` the real-world value, ``used`` the simulation's (after ``scale``), in ``unit``."""

    name: str
    real: float
    used: float
    unit: str
    meaning: str

    def line(self) -> str:
        value = f"{self.used:.4g} {self.unit}"
        if not math.isclose(self.real, self.used, rel_tol=1e-12):
            value = f"{self.real:.4g} {self.unit} real-world, {self.used:.4g} {self.unit} in the simulation"
        return f"  {self.name:<7} {value}: {self.meaning}"


@dataclass(frozen=True)
class Parameters:
    """The macro and micro groups of a scene and what they imply (module docstring).

    Attributes
    ----------
    scene, backend, force_model : names
    nodes : (M, N)
    spacing : (h1, h2) in m
    macro, micro : tuples of :class:`Parameter`
    scaling : str
        What ``scale`` did, in words.
    stiffness : (E h in N/m, D in N m)
        Koiter's and the orthotropic model's from their own E, nu, h: (E h / (1 - nu^2), D).
    dt : float
        The scene's time step (s).
    semi_implicit_step : float
        The stretching bound of the paper's semi-implicit scheme with these mu, eta on this grid (s).
    own_step : float
        The bound under the scene's own force model (s); inf when it lags nothing (the implicit schemes).
    bending_length : float
        Peirce's c = (D / (mu g))^(1/3) (m), D of ``stiffness``; nan without a bending rigidity or weight.
    fold_scale : float
        l_f = (D H / (mu g))^(1/4) (m), H the sheet's length along a2; nan likewise.
    narrowest_fold : float
        The narrowest fold predicted, NARROWEST_PER_FOLD_SCALE x l_f (m) (module docstring).
    """

    scene: str
    backend: str
    force_model: str
    nodes: tuple
    spacing: tuple
    macro: tuple
    micro: tuple
    scaling: str
    stiffness: tuple
    dt: float
    semi_implicit_step: float
    own_step: float
    bending_length: float
    fold_scale: float

    @property
    def narrowest_fold(self) -> float:
        """The narrowest fold predicted, :data:`NARROWEST_PER_FOLD_SCALE` x l_f (m); nan without a fold scale."""
        return NARROWEST_PER_FOLD_SCALE * self.fold_scale

    @property
    def resolved(self) -> bool:
        """The narrowest fold predicted spans at least :data:`RESOLVED` grid spacings (l_f at least
        :data:`FOLD_SCALE_SPACINGS` of them; module docstring)."""
        return self.narrowest_fold >= RESOLVED * min(self.spacing)

    def lines(self) -> list[str]:
        """The report, one item a line (``deformable params``, and the start of ``deformable run``)."""
        h = min(self.spacing)
        out = [(f"{self.scene}: {self.nodes[0]} x {self.nodes[1]} nodes on {self.backend}, spacing "
                f"{self.spacing[0]:.4g} x {self.spacing[1]:.4g} m, force model {self.force_model}"),
               "macro-control (section 3.1): inertia, damping and loads, scaled together by scale",
               *[p.line() for p in self.macro],
               "micro-control (sections 3.2, 4): the weights of the energy (13)",
               *[p.line() for p in self.micro]]
        out.append(f"  as a material about the flat rest state: tensile stiffness {self.stiffness[0]:.4g} N/m, bending "
                   f"rigidity D = {self.stiffness[1]:.4g} N m")
        out.append(self.scaling)
        step = self.semi_implicit_step
        if math.isfinite(step):
            where = ("within it" if self.dt < step else
                     f"{self.dt / step:.3g} times above it (the semi-implicit scheme would diverge at it)")
            out.append(f"stable step of the semi-implicit scheme (eqs. (22)-(27), the paper's force): dt < "
                       f"{step:.3g} s with these mu, eta; the scene's dt = {self.dt:g} s is {where}")
        else:
            out.append("stable step of the semi-implicit scheme: unbounded (eta = 0)")
        if not math.isfinite(self.own_step):
            out.append(f"  {self.force_model} lags nothing: the implicit step has no such bound (accuracy sets dt)")
        if math.isfinite(self.fold_scale):
            narrow = self.narrowest_fold
            verdict = "resolved" if self.resolved else "NOT resolved: folds narrower than the grid can show"
            refine = "" if self.resolved else f"; refine to h <= {narrow / RESOLVED:.3g} m"
            out.append(f"bending length (D / (mu g))^(1/3) = {self.bending_length:.3g} m (Peirce's cantilever test); "
                       f"the folds' length scale (D H / (mu g))^(1/4) = {self.fold_scale:.3g} m = "
                       f"{self.fold_scale / h:.3g} grid spacings (Cerda and Mahadevan 2003); narrowest fold "
                       f"predicted {NARROWEST_PER_FOLD_SCALE:.2g} x that = {narrow:.3g} m = {narrow / h:.3g} grid "
                       f"spacings: {verdict} (resolved when at least {RESOLVED:g}, l_f at least "
                       f"{FOLD_SCALE_SPACINGS:g} spacings, as measured on the drawn curtain{refine})")
        return out


def fold_scale(D: float, weight: float, height: float) -> float:
    """The folds' length scale l_f = (D H / (mu g))^(1/4) (m) of a sheet of bending rigidity ``D`` (N m) along
    the folds' direction, ``weight`` mu g (N/m^2, scaled) and ``height`` H (m) (Cerda and Mahadevan 2003); nan
    without a bending rigidity or a weight."""
    return (D * height / weight) ** 0.25 if D > 0 and weight > 0 else math.nan


def resolving_nodes(l_f: float, length: float, grids) -> int | None:
    """The first of ``grids`` (nodes along a length ``length`` m) on which folds of length scale ``l_f`` (m) are
    resolved by the rule of :attr:`Parameters.resolved`: l_f >= :data:`FOLD_SCALE_SPACINGS` x length / (n - 1);
    None when none is (or ``l_f`` is nan)."""
    for n in grids:
        if NARROWEST_PER_FOLD_SCALE * l_f >= RESOLVED * length / (n - 1):
            return int(n)
    return None


def parameters(cfg, model, backend: str) -> Parameters:
    """The parameters of a scene config ``cfg`` (:class:`~deformable.scenes.SceneConfig`) built as ``model``
    on ``backend`` (module docstring)."""
    s = cfg.scale
    macro = (Parameter("mu", cfg.mu, s * cfg.mu, "kg/m^2", "mass density"),
             Parameter("gamma", cfg.gamma, s * cfg.gamma, "kg/(m^2 s)", "damping density (eq. (11))"),
             Parameter("f", cfg.mu * cfg.g, s * cfg.mu * cfg.g, "N/m^2",
                       f"gravity's force density mu g (g = {cfg.g:g} m/s^2)"
                       + (f"; the scene's other applied forces times {s:g} too" if s != 1 else "")))
    if isinstance(getattr(cfg, "pressure", None), float):  # a scene loaded by a pressure (the panel, Figs 1-2)
        macro += (Parameter("p", cfg.pressure, s * cfg.pressure, "N/m^2",
                            "pressure along the sheet's normal (a follower load)"),)
    fm = ForceModel.of(model.force_model)
    own = hasattr(fm, "stiffnesses")  # Koiter's shell, the orthotropic sheet: their own E, nu, h
    if own:
        micro = tuple(Parameter(k, getattr(fm, k), getattr(fm, k), u, m) for k, u, m in (
            ("E", "Pa", "Young's modulus"), ("nu", "", "Poisson's ratio"), ("h", "m", "thickness"))
            if hasattr(fm, k))
        stiffness = fm.stiffnesses
    elif getattr(cfg, "fabric", ""):  # a named fabric: its warp (a1) and weft (a2) weights and stiffnesses
        fabric = cfg.named_fabric()
        eta, xi = fabric.weights(fm.name)
        micro = (Parameter("eta", eta[0, 0], eta[0, 0], "N/m", f"stretching weight eta_11 (warp); eta_22 (weft) "
                           f"{eta[1, 1]:.4g}, eta_12 {eta[0, 1]:.4g} N/m: fabric {cfg.fabric!r}, {fabric.name}"),
                 Parameter("xi", xi[0, 0], xi[0, 0], "N m", f"bending weight xi_11 (warp); xi_22 (weft) "
                           f"{xi[1, 1]:.4g}, xi_12 {xi[0, 1]:.4g} N m"))
        stiffness = (fabric.tensile[0], fabric.bending[0])  # along a1, the warp: the curtain's folds bend it
    else:
        micro = (Parameter("eta", cfg.eta, cfg.eta, "N/m", f"stretching weight eta_11 = eta_22; eta_12 = "
                           f"{cfg.shear:g} eta"),
                 Parameter("xi", cfg.xi, cfg.xi, "N m", f"bending weight xi_11 = xi_22; xi_12 = {cfg.shear:g} xi"))
        se, sx = fm.stiffness
        stiffness = (2 * se * cfg.eta, sx * cfg.xi)
    D, weight = stiffness[1], s * cfg.mu * cfg.g  # the tension's scale: the weight of the sheet, scaled
    both = D > 0 and weight > 0
    peirce = (D / weight) ** (1 / 3) if both else math.nan
    folds = fold_scale(D, weight, cfg.size[1])  # fold_wavelength's
    return Parameters(scene=cfg.scene, backend=backend, force_model=fm.name, nodes=tuple(model.scene.sheet.nodes),
                      spacing=tuple(model.spacing), macro=macro, micro=micro, scaling=cfg.scaling(),
                      stiffness=stiffness, dt=cfg.dt, semi_implicit_step=model.stable_step("tpbf87"),
                      own_step=model.stable_step(), bending_length=peirce, fold_scale=folds)
