r"""The paper's example scenes (section 5), in SI units, and scene files (TOML).

Every scene is a frozen *config* of plain numbers (a dataclass whose defaults
are the scene's values) and a builder that turns it into a
:class:`~deformable.scene.Scene`. The registry :data:`SCENES` maps a name to a
:class:`SceneSpec`; calling a spec, or the module-level function of the same
name, gives the Scene on a node grid::

    scene = scenes.curtain(nodes=(32, 32))             # a Scene
    cfg = scenes.config("curtain", xi=1e-4)            # the config, overridden
    cfg = scenes.read_toml("my-curtain.toml")          # scene = "curtain" + fields
    scene = scenes.build(cfg)

The model. Every scene runs the energy-consistent ("variational") model by
default: its force is the gradient of the energy (13), so a flat sheet resists
bending and survives compression, which the folding scenes go through. The
paper's force (14) is one field away (``force_model = "tpbf87"``, or
``deformable run --force-model tpbf87``): under it a flat sheet has no linear
bending stiffness and compression has no restoring force, so the drawn curtain
zigzags at the grid scale (xi = 0) or crumples (xi > 0) (docs/design.md,
"Findings"). The weight tensors are full, ``eta_12 = shear eta`` and
``xi_12 = shear xi`` with ``shear = 1``: the isotropic sheet with Poisson ratio
0 (with the variational model, the St Venant-Kirchhoff plate of E h = 8 eta,
D = 2 xi). The paper sets eta_12 = xi_12 = 0 (``shear = 0``); without shear
resistance a compressed sheet shortens in its own plane by shearing (its
fibres zigzag in the plane at no cost in G_11, G_22 or B), and the drawn
curtain never folds out of its plane.

The same eta, xi are a different material under the two force models: about
eta = 20 N/m the variational force is 4 times stiffer in stretching, and 2
times in bending, than the paper's (:func:`equivalent_weights` maps them).

Macro control (section 3.1): ``scale`` multiplies mu, gamma and the applied
forces (gravity through mu, the curtain's push, the coils' stiffness, the
wind's drag) while eta and xi stay: the motion is then the one the unscaled
sheet would have with eta / scale and xi / scale, a relatively softer sheet
(:meth:`SceneConfig.scaling`). The fields mu and gamma are the real-world
values before scaling, so a scene file states the physics and its scaling
apart, as section 4 recommends.

Scenes (paper section 5), and how they differ from the paper's text:

``hanging``
    A square cloth, initially horizontal, pinned at its two top corners,
    falling and swinging under gravity (not in the paper; the simplest scene).
``curtain`` (Figs 3-4)
    The curtain hangs in the vertical x-z plane. Its top row keeps its height
    on the rod and slides along it (``Slide("top", ("x", "y"))``: rings slide
    along x and swing out along y); the rod end at a1 = 0 is pinned and the
    other end is drawn along the rod (a prescribed motion, a smooth ramp over
    ``draw_time``), gathering the top to ``1 - gather`` of its width. The
    cloth below, compressed across, folds by itself: nothing in the loads
    selects a wavelength. A small seeded perturbation of the flat start
    (``noise``, white over the wavelengths 2 L1 / 32 .. 2 L1 along the width)
    decides which way each fold goes, identically on every grid and backend.
    The fold width then follows from the material, the bending length of a
    sheet held by its weight (:func:`fold_wavelength`): xi = 1e-4 N m, a
    curtain fabric whose folds the shipped 64 x 64 grid resolves (the
    paper's xi = 0 has no length scale under the variational model, and a
    limp cloth's folds, xi = 1e-5, follow the grid on every grid tried).
    Differences from the paper: its curtain is folded by "external forces
    perpendicular to the plane on the upper part" and its top restricted "to
    the axis where it should slide"; here the top is drawn and may swing out
    of the rod's line (held on a line, every top node would be a hinge at
    y = 0 and folds would start at grid scale under the rod). The paper's perpendicular push
    stays available (``push``; ``folds > 0`` gives it the earlier sin pattern,
    which selects the number of folds). ``rings = 1`` carries the top on
    hooks drawn together uniformly instead (``hooks`` their spacing): an
    experiment that folds at the grid scale at the quick grids
    (docs/design.md, "Findings").
``curtain-silky`` (Fig. 5)
    The curtain with ``scale = 20`` (mu, gamma, f times 20, section 3.1), on
    a 64 x 64 grid that resolves its shorter bending length. The paper keeps
    xi = 0 here; under the variational model xi = 0 has no length scale and
    folds at grid scale, so the silky curtain keeps the curtain's xi.
``paper`` (Fig. 6)
    The silky curtain with 16 times its curvature resistance, so that the
    fold wavelength doubles ((16)^(1/4) = 2). The paper's xi = 3e-6 N m (under
    its force, 1.5e-6 N m in the variational model's terms) is below the
    silky curtain's xi here and would make the paper *softer*, not stiffer.
``flag`` (Figs 7-8)
    A flag on its pole (the edge a1 = 0 pinned), the paper's "coil force" on
    its free side: two springs from the free corners to anchors beyond the
    flag that swing across it (``swing``, ``frequency``), and wind along the
    flag (aerodynamic pressure on the normal with the relative velocity,
    :class:`~deformable.physics.forces.Wind`), which presses on every fold the coils
    raise and damps the motion across the flag. The coils drive the waves
    from the free side, so they travel towards the pole (a real flag's waves
    come from the flow and travel to its free edge; the paper names only the
    coil). The springs keep the flag out against gravity, which a real flag's
    skin friction does. The swing is 6 Hz (the paper gives none) so that the
    wave is shorter than the flag: its phase speed along the flag is about
    7 m/s (set by the coils' tension), a wavelength of 1.1-1.2 m at 6 Hz
    against the flag's 1.2 m; at 4 Hz (1.75 m) the phase changed by 3.06 rad
    (FD 32 x 32) and 3.11 rad (FE 16 x 16 elements) from pole to tip, less
    than half a wave, at 6 Hz by 5.2 and 4.4 rad (the paper study's flag
    section measures it).

Contact scenes (:mod:`deformable.contact.obstacles`, :mod:`deformable.contact`):

``floor``
    A square cloth, flat and horizontal, falling onto the floor (a
    :class:`~deformable.contact.obstacles.HalfSpace` at z = 0) and settling there.
``sphere``
    A square cloth dropped centred onto a ball, draping over it.
``drape``
    The Cusick drape test (Cusick 1968, "The measurement of fabric drape",
    J. Text. Inst. 59, 253-260; BS 5058): a square cloth 30 cm a side on a
    round table 18 cm across (a :class:`~deformable.contact.obstacles.Cylinder` with a
    rounded rim), of a stiff fabric (xi = 3e-4 N m, a bending length of
    6.7 cm) whose folds the quick grids resolve, with four contact points per
    cell side (``Contact(samples=4)``) so that the table's rim holds the cloth
    where it is and not at the nearest node. The drape coefficient ``DC = (A_s - A_d) / (A_D - A_d)``
    (:func:`validation.harness.drape.drape_coefficient`), with A_s the area of the
    draped cloth's shadow, A_d the table's and A_D the flat cloth's, is 1 for
    a cloth that stays flat and 0 for one that hangs straight down.

Every scene takes further obstacles from a scene file, ``[[obstacles]]``
tables (``kind = "plane" | "sphere" | "box" | "cylinder"`` and the obstacle's
fields), and the contact settings from a ``[contact]`` table
(:class:`deformable.Contact`); unknown keys are errors, as elsewhere.

Stability. With the variational model the implicit-Euler step has no
stretching bound; the default dt (5 ms) keeps about three Newton iterations a
step. Under the paper's force the semi-implicit step is bounded by about
``h sqrt(mu / (2 eta G))`` (the backend's ``stable_step()``): ``deformable
run`` then takes half of it when the scene's dt is larger.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import tomllib
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Callable, ClassVar

import numpy as np

from ..contact.obstacles import Cylinder, HalfSpace, Obstacle, Sphere
from ..contact.obstacles import from_table as obstacle_from_table
from ..contact.settings import Contact
from ..dynamics.stepper import DT_MIN
from ..errors import InputError
from ..geometry.sheet import Sheet
from ..geometry.surfaces import Plane
from ..physics.force_models import ForceModel
from ..physics.forces import BodyForce, Gravity, Spring, Wind
from ..physics.material import Material
from ..scene.constraints import Pin, Slide
from ..scene.scene import Scene

__all__ = [
    "SCENES", "SceneSpec", "read_toml_text", "SceneConfig", "HangingConfig", "CurtainConfig", "FlagConfig", "Plane",
    "hanging", "curtain", "curtain_silky", "paper", "flag", "floor", "sphere", "drape", "FloorConfig", "SphereConfig",
    "DrapeConfig", "config", "build", "read_toml", "to_toml", "run_table",
    "equivalent_weights", "fold_wavelength", "smooth_ramp", "FoldNoise",
]

log = logging.getLogger(__name__)


# -- geometry ------------------------------------------------------------------
#: the vertical x-z plane: a1 along x, a2 up (the curtain and the flag hang in it)
VERTICAL = Plane(e1=(1.0, 0.0, 0.0), e2=(0.0, 0.0, 1.0))
#: the horizontal x-y plane (the default rest shape)
HORIZONTAL = Plane()

def equivalent_weights(eta: float, xi: float, source: str = "tpbf87", target: str = "variational"):
    """(eta, xi) under ``target`` with the linearised stiffness of (eta, xi) under ``source``.

    About a rest state, the paper's force (14) ``-d_i(eta (G - G0) d_j r) + ...``
    has the stretching stiffness eta and the bending stiffness xi; the gradient
    of the energy (13) has 4 eta (G = r . r is quadratic in r, and (G - G0)^2
    again) and 2 xi. So ``equivalent_weights(20, 1e-5)`` is (5, 5e-6): the
    variational weights of the same linear material. The frozen model counts
    like tpbf87 (its alpha, beta are the paper's). Any registered force model
    counts by its own :attr:`~deformable.physics.ForceModel.stiffness`.
    """
    (se, sx), (te, tx) = ForceModel.lookup(source).stiffness, ForceModel.lookup(target).stiffness
    return eta * se / te, xi * sx / tx


def smooth_ramp(s):
    """0 before s = 0, 1 after s = 1, ``s^3 (10 - 15 s + 6 s^2)`` between: no jump in velocity or acceleration."""
    s = np.clip(s, 0.0, 1.0)
    return s**3 * (10.0 - 15.0 * s + 6.0 * s * s)


def fold_wavelength(xi: float, mu: float, g: float, height: float, scale: float = 1.0,
                    force_model: str = "variational") -> float:
    r"""The bending-length scale of the folds of a hanging sheet, ``(D H / (mu g))^(1/4)`` (m).

    A sheet hanging under its own weight and compressed across its width
    wrinkles where its bending stiffness D balances the stiffness of the
    tension that holds it straight: Cerda and Mahadevan (2003, "Geometry and
    physics of wrinkling", Phys. Rev. Lett. 90, 074302) give
    ``lambda ~ (D / K)^(1/4)`` with the tension's effective stiffness
    ``K = T / H^2``; a curtain's tension is its weight below, T ~ mu g H, so
    ``lambda ~ (D H / (mu g))^(1/4)``. The number of folds across a given
    width scales as ``xi^(-1/4)``; the prefactor is the curtain's own (the
    paper study measures it). D = 2 xi under the variational model, xi under
    the paper's force; mu and the forces are scaled together, so ``scale``
    divides D.
    """
    D = xi * ForceModel.lookup(force_model).stiffness[1]
    return (D * height / (scale * mu * g)) ** 0.25


@dataclass(frozen=True)
class FoldNoise:
    """The curtain's start: its rest plane plus a small seeded ripple along y, a Surface with exact derivatives.

    ``y = noise * sum_k c_k sin(k pi a1 / L1 + phi_k)`` for k = 1..modes, c_k
    standard normal over sqrt(modes / 2) (so the RMS is about ``noise``) and
    phi_k uniform: white over the wavelengths 2 L1 / modes .. 2 L1, the same
    function on every grid and backend.
    """

    width: float
    noise: float
    seed: int
    modes: int = 32

    def _coefficients(self):
        rng = np.random.default_rng(self.seed)
        c = rng.normal(size=self.modes) / math.sqrt(self.modes / 2)
        phi = rng.uniform(0.0, 2.0 * math.pi, self.modes)
        k = np.arange(1, self.modes + 1) * math.pi / self.width
        return self.noise * c, k, phi

    def _ripple(self, a1, order):
        c, k, phi = self._coefficients()
        a1 = np.asarray(a1, float)[..., None]
        if order == 0:
            return np.sum(c * np.sin(k * a1 + phi), axis=-1)
        return np.sum(c * k * np.cos(k * a1 + phi), axis=-1)

    def r(self, a1, a2):
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.stack([a1, self._ripple(a1, 0), a2], axis=-1)

    def r1(self, a1, a2):
        a1, a2 = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.stack([np.ones_like(a1), self._ripple(a1, 1), np.zeros_like(a1)], axis=-1)

    def r2(self, a1, a2):
        a1, _ = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.broadcast_to(np.array([0.0, 0.0, 1.0]), a1.shape + (3,)).copy()

    def r12(self, a1, a2):
        a1, _ = np.broadcast_arrays(np.asarray(a1, float), np.asarray(a2, float))
        return np.zeros(a1.shape + (3,))


# -- configs -------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class SceneConfig:
    """Fields every scene has (SI units).

    Parameters
    ----------
    scene : str
        Registry name of the scene kind.
    size : (L1, L2)
        Sheet size in m (the parameter rectangle, metres at rest).
    nodes : (M, N)
        Node grid.
    mu : float
        Real-world mass density in kg/m^2 (the scene uses ``scale * mu``).
    gamma : float
        Real-world damping density in kg/(m^2 s) (the scene uses ``scale * gamma``).
    eta, xi : float
        Stretching (N/m) and bending (N m) weights of eq. (13), eta_11 = eta_22 = eta, xi_11 = xi_22 = xi.
    shear : float
        eta_12 = shear eta and xi_12 = shear xi (1: the isotropic sheet with
        Poisson ratio 0; the paper: 0).
    g : float
        Gravity in m/s^2 (the force mu g scales with mu).
    scale : float
        The section 3.1 factor on mu, gamma and the applied forces (:meth:`scaling`).
    dt : float
        Default time step (s).
    t_end : float
        Default simulated time (s).
    force_model : str
        "variational" (default) or another registered force model (:class:`deformable.ForceModel`).
    alpha, beta : float
        The "frozen" model's weights, given directly (section 3.2): alpha_11 =
        alpha_22 = alpha (N/m), beta_11 = beta_22 = beta and beta_12 = shear
        beta (N m); alpha_12 = 0 (a cross weight of r_1 . r_2 would make the
        membrane energy indefinite). The frozen model needs one of them
        positive; the other models take eta and xi, and refuse alpha and beta.
    rest_metric : (G0_11, G0_22)
        The rest metric G0 = diag(G0_11, G0_22) (dimensionless); (1, 1) is the
        flat rest shape itself. A value below 1 prestresses the sheet: it is
        in tension until its fibres shrink to sqrt(G0_ii) of their length.
    rest_curvature : (B0_11, B0_22)
        The rest curvature B0 = diag(B0_11, B0_22) (1/m); (0, 0) is the flat
        rest shape. (1 / R, 0) is a cylinder of radius R along a2, a sheet that
        curls back into it; both non-zero on a flat metric is no surface at
        all (eq. (10): ``deformable check`` says so, and the Scene warns).
    obstacles : tuple of Obstacle
        Obstacles besides the scene's own (scene files: ``[[obstacles]]`` tables).
    contact : Contact or None
        How the sheet meets the obstacles (scene files: a ``[contact]`` table); None: ``Contact()``.
    """

    scene: str
    size: tuple = (1.0, 1.0)
    nodes: tuple = (32, 32)
    mu: float = 0.2
    gamma: float = 0.1
    eta: float = 20.0
    xi: float = 1e-5
    shear: float = 1.0
    g: float = 9.81
    scale: float = 1.0
    dt: float = 5e-3
    t_end: float = 2.0
    force_model: str = "variational"
    alpha: float = 0.0
    beta: float = 0.0
    rest_metric: tuple = (1.0, 1.0)
    rest_curvature: tuple = (0.0, 0.0)
    obstacles: tuple = ()
    contact: Contact | None = None
    #: fields that must be positive, and non-negative (subclasses add theirs)
    POSITIVE: ClassVar[tuple] = ("dt", "t_end", "mu", "scale")
    NON_NEGATIVE: ClassVar[tuple] = ("gamma", "eta", "xi", "alpha", "beta")

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "scene":
                if value not in SCENES:
                    raise InputError(f"unknown scene {value!r}; known scenes: {', '.join(SCENES)}")
            elif f.name == "obstacles":
                if not isinstance(value, (dict, Obstacle, list, tuple)):
                    raise InputError(f"scene field obstacles must be [[obstacles]] tables (or obstacles), got {value!r}",
                                     field="obstacles", value=value)
                tables = [value] if isinstance(value, (dict, Obstacle)) else list(value)
                object.__setattr__(self, f.name, tuple(obstacle_from_table(t, f"scene field obstacles[{k}]")
                                                       for k, t in enumerate(tables)))
            elif f.name == "contact":
                if value is not None:
                    object.__setattr__(self, f.name, Contact.from_table(value, "scene field contact"))
            elif f.name == "force_model":
                if not isinstance(value, str) or value not in ForceModel.names():
                    raise InputError(f"scene field force_model must be one of {', '.join(ForceModel.names())}, "
                                     f"got {value!r}", field="force_model", value=value)
            elif f.name in ("size", "nodes", "rest_metric", "rest_curvature"):
                kind = int if f.name == "nodes" else float
                try:
                    pair = tuple(value)
                    ok = len(pair) == 2 and all(
                        not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v) and kind(v) == v
                        for v in pair
                    )
                except TypeError:
                    ok = False
                if not ok:
                    raise InputError(f"scene field {f.name} must be two {kind.__name__}s, got {value!r}")
                object.__setattr__(self, f.name, tuple(kind(v) for v in pair))
            elif f.type in (int, "int"):
                if (isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value)
                        or int(value) != value):
                    raise InputError(f"scene field {f.name} must be an integer, got {value!r}")
                object.__setattr__(self, f.name, int(value))
            else:
                if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                    raise InputError(f"scene field {f.name} must be a finite number, got {value!r}")
                object.__setattr__(self, f.name, float(value))
        for name in self.POSITIVE:
            if getattr(self, name) <= 0:
                raise InputError(f"scene field {name} must be positive, got {getattr(self, name)!r}")
        for name in self.NON_NEGATIVE:
            if getattr(self, name) < 0:
                raise InputError(f"scene field {name} must be non-negative, got {getattr(self, name)!r}")
        if not 0 <= self.shear <= 1:
            raise InputError(f"scene field shear must lie in [0, 1] (eta_12 <= eta keeps eq. (13) definite), "
                             f"got {self.shear!r}")
        if min(self.rest_metric) <= 0 or min(self.size) <= 0:
            raise InputError(f"scene fields size and rest_metric must be positive, got {self.size!r}, "
                             f"{self.rest_metric!r}", field="size", value=self.size)
        if min(self.nodes) < 3:
            raise InputError(f"scene field nodes must be at least 3 a side, got {self.nodes!r}")
        if self.dt < DT_MIN:
            raise InputError(f"scene field dt must be at least {DT_MIN:g} s, got {self.dt!r}", field="dt",
                             value=self.dt)
        for name in ("mu", "gamma"):
            if not math.isfinite(self.scale * getattr(self, name)):
                raise InputError(f"scene fields scale and {name}: scale * {name} = {self.scale!r} * "
                                 f"{getattr(self, name)!r} is not a finite number", field=name,
                                 value=getattr(self, name))
        direct = self._weights_given()
        if direct and not (self.alpha > 0 or self.beta > 0):
            raise InputError(f"scene fields alpha and beta: the {self.force_model} force model needs alpha > 0 or "
                             "beta > 0 (its weights, given directly; e.g. alpha=1 beta=1e-3)", field="alpha",
                             value=self.alpha)
        if not direct and (self.alpha or self.beta):
            raise InputError(f"scene fields alpha = {self.alpha!r}, beta = {self.beta!r} are the frozen model's "
                             f"weights; the {self.force_model} model takes eta and xi (set force_model = \"frozen\")",
                             field="alpha", value=self.alpha)

    def _weights_given(self) -> bool:
        """The force model takes its weights as alpha and beta, given directly (the frozen model, section 3.2)."""
        return ForceModel.lookup(self.force_model).weights == ("alpha", "beta")

    def scene_kwargs(self) -> dict:
        """Keyword arguments of Scene common to every scene (force model, rest metric and curvature, name)."""
        G0 = None if self.rest_metric == (1.0, 1.0) else np.diag(self.rest_metric)
        B0 = None if self.rest_curvature == (0.0, 0.0) else np.diag(self.rest_curvature)
        return dict(force_model=self.force_model, rest_metric=G0, rest_curvature=B0, name=self.scene,
                    obstacles=self.obstacles, contact=self.contact)

    def replace(self, **changes) -> SceneConfig:
        """A copy with some fields changed; an unknown field is a ValueError naming it."""
        known = {f.name for f in fields(self)}
        for key in changes:
            if key not in known:
                raise InputError(f"unknown key {key!r} for scene {self.scene!r}; known keys: "
                                 f"{', '.join(sorted(known))}", field=key, value=changes[key])
        if isinstance(changes.get("contact"), dict):  # a [contact] table overrides the scene's own settings
            changes["contact"] = Contact.from_table(changes["contact"], "scene field contact", base=self.contact)
        return dataclasses.replace(self, **changes)

    def material(self) -> Material:
        """mu, gamma times ``scale``; eta and xi as full tensors (``shear`` off the diagonal)."""
        def tensor(w):
            return np.array([[w, self.shear * w], [self.shear * w, w]])

        frozen = {}
        if self._weights_given():  # alpha_12 = 0, beta_12 = shear beta (the field docs of SceneConfig)
            frozen = dict(alpha=np.diag([self.alpha, self.alpha]), beta=tensor(self.beta))
        return Material(mu=self.scale * self.mu, gamma=self.scale * self.gamma, eta=tensor(self.eta),
                        xi=tensor(self.xi), **frozen)

    def scaling(self) -> str:
        """What ``scale`` does, in words (section 3.1)."""
        if self.scale == 1:
            return "scale 1: mu, gamma and the forces are the real-world values"
        return (f"scale {self.scale:g}: mu, gamma and the applied forces are {self.scale:g} times the real-world "
                f"values while eta and xi stay, so the sheet moves as the real one would with eta = "
                f"{self.eta / self.scale:.4g} N/m and xi = {self.xi / self.scale:.4g} N m (section 3.1)")


@dataclass(frozen=True, kw_only=True)
class HangingConfig(SceneConfig):
    """A cloth pinned at its two top corners, starting horizontal (no extra fields)."""


@dataclass(frozen=True, kw_only=True)
class CurtainConfig(SceneConfig):
    """The opening curtain (Figs 3-6).

    Parameters
    ----------
    gather : float
        How far the drawn end of the rod travels, as a fraction of the width
        (0.6: the top gathers to 40 % of it); 0 leaves the top in place.
    draw_time : float
        Seconds over which it is drawn (a smooth ramp, :func:`smooth_ramp`).
    rings : int
        0 (default): the top row slides on the rod and its end at a1 = L1 is drawn. 1: the top hangs from
        hooks on rings that are drawn together uniformly, each hook at a1 carried to x = a1 (1 - gather
        ramp), holding its height, free to swing along y; the top between hooks slides in the rod's plane.
        An experiment (issue 13): at the quick grids it folds at the grid scale (docs/design.md, "Findings").
    hooks : float
        With ``rings = 1``: the spacing of the hooks along the top (m, rounded to whole grid spacings;
        :func:`hook_nodes`); 0: a hook at every top node.
    noise : float
        RMS of the start's ripple across the plane (m, :class:`FoldNoise`).
    seed : int
        Seed of the ripple.
    push : float
        Force density perpendicular to the rest plane on the upper part
        (N/m^2, real-world, along y), the paper's mechanism; 0 by default.
    folds : float
        0: a uniform push; n > 0: ``push sin(pi n a1 / L1)``, which selects n
        half-waves (the earlier scene's load).
    taper : float
        The push at the hem as a fraction of the push at the rod (linear between).
    """

    gather: float = 0.6
    draw_time: float = 1.6
    rings: int = 0
    hooks: float = 0.0
    noise: float = 1e-3
    seed: int = 1
    push: float = 0.0
    folds: float = 0.0
    taper: float = 0.5
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("draw_time",)
    NON_NEGATIVE: ClassVar[tuple] = SceneConfig.NON_NEGATIVE + ("noise", "folds", "seed", "hooks")
    RINGS: ClassVar[tuple] = (0, 1)

    def __post_init__(self):
        super().__post_init__()
        if not 0 <= self.gather < 1:
            raise InputError(f"scene field gather must lie in [0, 1), got {self.gather!r}")
        if self.rings not in self.RINGS:
            raise InputError(f"scene field rings must be 0 (the drawn end) or 1 (hooks drawn together), got "
                             f"{self.rings!r}")


@dataclass(frozen=True, kw_only=True)
class FlagConfig(SceneConfig):
    """The waving flag (Figs 7-8).

    Parameters
    ----------
    wind : float
        Wind speed along +x, away from the pole (m/s).
    drag : float
        c = rho C_d / 2 of the wind's pressure (kg/m^3; air 0.6), real-world.
    coil : float
        Stiffness of each of the two coils at the free corners (N/m), real-world.
    reach : float
        How far beyond the free edge the coils' anchors are (m).
    swing : float
        Amplitude of the anchors' swing across the flag, along y (m).
    frequency : float
        Frequency of the swing (Hz).
    ramp : float
        Seconds over which the swing grows to its amplitude.
    """

    wind: float = 10.0
    drag: float = 0.6
    coil: float = 30.0
    reach: float = 0.1
    swing: float = 0.15
    frequency: float = 6.0
    ramp: float = 0.5
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("ramp",)
    NON_NEGATIVE: ClassVar[tuple] = SceneConfig.NON_NEGATIVE + ("drag", "coil", "swing", "frequency")


@dataclass(frozen=True, kw_only=True)
class FloorConfig(SceneConfig):
    """A cloth falling onto the floor (the plane z = 0).

    Parameters
    ----------
    height : float
        The sheet's starting height above the floor (m); from rest it lands at sqrt(2 g height).
    tilt : float
        The start's tilt about the a2 direction (degrees; 0: falling flat).
    """

    height: float = 0.3
    tilt: float = 0.0
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("height",)


@dataclass(frozen=True, kw_only=True)
class SphereConfig(SceneConfig):
    """A cloth dropped centred onto a ball whose top is at z = 0.

    Parameters
    ----------
    radius : float
        The ball's radius (m).
    gap : float
        The sheet's starting height above the ball's top (m).
    """

    radius: float = 0.25
    gap: float = 0.05
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("radius", "gap")


@dataclass(frozen=True, kw_only=True)
class DrapeConfig(SceneConfig):
    """The Cusick drape test: a cloth centred on a round table whose top is at z = 0.

    Parameters
    ----------
    table_radius : float
        The table's radius (m; BS 5058: 0.09).
    table_thickness : float
        Its thickness (m).
    rim : float
        The radius of its rounded rim (m).
    gap : float
        The sheet's starting height above the table (m).
    """

    table_radius: float = 0.09
    table_thickness: float = 0.02
    rim: float = 0.003
    gap: float = 5e-4
    POSITIVE: ClassVar[tuple] = SceneConfig.POSITIVE + ("table_radius", "table_thickness", "gap")
    NON_NEGATIVE: ClassVar[tuple] = SceneConfig.NON_NEGATIVE + ("rim",)

    def table(self) -> Cylinder:
        """The table: a cylinder under the sheet's centre, its top at z = 0."""
        L1, L2 = self.size
        return Cylinder(center=(0.5 * L1, 0.5 * L2, -0.5 * self.table_thickness), radius=self.table_radius,
                        height=self.table_thickness, rounding=self.rim)


# -- builders ------------------------------------------------------------------
def _hanging(cfg: HangingConfig) -> Scene:
    sheet = Sheet(size=cfg.size, nodes=cfg.nodes, rest=HORIZONTAL)
    return Scene(sheet, cfg.material(), forces=[Gravity(cfg.g)], constraints=[Pin(["top-left", "top-right"])],
                 **cfg.scene_kwargs())


def _curtain(cfg: CurtainConfig) -> Scene:
    L1, L2 = cfg.size
    start = FoldNoise(L1, cfg.noise, cfg.seed) if cfg.noise > 0 else VERTICAL
    sheet = Sheet(size=cfg.size, nodes=cfg.nodes, rest=VERTICAL, initial=start)
    forces = [Gravity(cfg.g)]
    if cfg.push:
        push, k = cfg.scale * cfg.push, math.pi * cfg.folds / L1

        def perpendicular(a1, a2, t):
            pattern = np.sin(k * a1) if cfg.folds else np.ones_like(a1)
            fy = push * pattern * (cfg.taper + (1.0 - cfg.taper) * a2 / L2)
            return np.stack([np.zeros_like(fy), fy, np.zeros_like(fy)], axis=-1)

        forces.append(BodyForce(perpendicular))
    if cfg.rings:
        constraints = _rings(cfg)
    else:  # the top slides on the rail; its end at a1 = L1 is drawn
        constraints = [Slide("top", ("x", "y")), Pin("top-left")]
        if cfg.gather:
            travel, duration = cfg.gather * L1, cfg.draw_time

            def draw(t):
                return (-travel * float(smooth_ramp(t / duration)), 0.0, 0.0)

            constraints.append(Pin("top-right", motion=draw))
    return Scene(sheet, cfg.material(), forces=forces, constraints=constraints, **cfg.scene_kwargs())


def hook_nodes(cfg: CurtainConfig) -> np.ndarray:
    """The indices m of the top-row nodes that carry the curtain's hooks (``rings = 1``), both ends included.

    ``hooks = 0``: every top node; ``hooks = s > 0``: the nodes nearest to a1 = 0, s, 2 s, ... and the last.
    """
    M = cfg.nodes[0]
    if cfg.hooks == 0:
        return np.arange(M)
    step = max(1, int(round(cfg.hooks * (M - 1) / cfg.size[0])))
    return np.unique(np.append(np.arange(0, M, step), M - 1))


def _rings(cfg: CurtainConfig) -> list:
    """The top carried by hooks on rings, the rings drawn together uniformly towards a1 = 0 (``rings = 1``).

    A hook at a1 keeps its height and is carried to x = a1 (1 - gather ramp(t / draw_time)); it swings freely
    along y (a ring on the rod). The top nodes between hooks slide in the rod's horizontal plane.
    """
    L1, (M, N) = cfg.size[0], cfg.nodes
    hooks = hook_nodes(cfg)
    constraints = [Slide("top", ("x", "y"))]  # the rod holds the height (FE: also the slope along the top)

    def carried(a1):
        def motion(t):
            return (-a1 * cfg.gather * float(smooth_ramp(t / cfg.draw_time)), 0.0, 0.0)
        return motion

    for m in hooks:
        a1 = m * L1 / (M - 1)
        constraints.append(Pin(np.array([[m, N - 1]]), motion=carried(a1) if cfg.gather and m else None,
                               axes=("x", "z")))
    return constraints


def _flag(cfg: FlagConfig) -> Scene:
    L1, L2 = cfg.size
    sheet = Sheet(size=cfg.size, nodes=cfg.nodes, rest=VERTICAL)
    omega = 2.0 * math.pi * cfg.frequency

    def anchor(z):
        def where(t):
            return (L1 + cfg.reach, cfg.swing * math.sin(omega * t) * float(smooth_ramp(t / cfg.ramp)), z)
        return where

    coils = [Spring((L1, z), anchor(z), cfg.scale * cfg.coil) for z in (0.0, L2)]
    forces = [Gravity(cfg.g), Wind((cfg.wind, 0.0, 0.0), cfg.scale * cfg.drag), *coils]
    return Scene(sheet, cfg.material(), forces=forces, constraints=[Pin("left")], **cfg.scene_kwargs())


def _with_obstacles(cfg: SceneConfig, *own: Obstacle) -> dict:
    """scene_kwargs with the scene's own obstacles before the config's extra ones."""
    kwargs = cfg.scene_kwargs()
    kwargs["obstacles"] = own + tuple(cfg.obstacles)
    return kwargs


def _floor(cfg: FloorConfig) -> Scene:
    a = math.radians(cfg.tilt)
    start = Plane(origin=(0.0, 0.0, cfg.height), e1=(math.cos(a), 0.0, math.sin(a)))
    sheet = Sheet(size=cfg.size, nodes=cfg.nodes, rest=HORIZONTAL, initial=start)
    return Scene(sheet, cfg.material(), forces=[Gravity(cfg.g)], **_with_obstacles(cfg, HalfSpace()))


def _sphere(cfg: SphereConfig) -> Scene:
    L1, L2 = cfg.size
    sheet = Sheet(size=cfg.size, nodes=cfg.nodes, rest=HORIZONTAL, initial=Plane(origin=(0.0, 0.0, cfg.gap)))
    ball = Sphere(center=(0.5 * L1, 0.5 * L2, -cfg.radius), radius=cfg.radius)
    return Scene(sheet, cfg.material(), forces=[Gravity(cfg.g)], **_with_obstacles(cfg, ball))


def _drape(cfg: DrapeConfig) -> Scene:
    sheet = Sheet(size=cfg.size, nodes=cfg.nodes, rest=HORIZONTAL, initial=Plane(origin=(0.0, 0.0, cfg.gap)))
    return Scene(sheet, cfg.material(), forces=[Gravity(cfg.g)], **_with_obstacles(cfg, cfg.table()))


@dataclass(frozen=True)
class SceneSpec:
    """A registry entry: the config class, this scene's defaults and its builder.

    Calling it, ``spec(nodes=(M, N), **fields)``, builds the Scene.
    """

    name: str
    config_class: type
    defaults: dict
    builder: Callable
    summary: str

    def config(self, **fields_) -> SceneConfig:
        """The scene's config with some fields overridden (unknown fields: ValueError)."""
        base = self.config_class(scene=self.name, **self.defaults)
        return base.replace(**fields_) if fields_ else base

    @property
    def dt(self) -> float:
        """The default time step (s)."""
        return self.config().dt

    def __call__(self, nodes=None, **fields_) -> Scene:
        if nodes is not None:
            fields_["nodes"] = tuple(nodes)
        return self.builder(self.config(**fields_))


# Real-world starting point (section 4): a curtain fabric of 0.2 kg/m^2, E h = 8 eta = 160 N/m, D = 2 xi = 2e-4 N m
# (a bending length (D / (mu g))^(1/3) of 4.7 cm). Its folds (fold_wavelength 0.105 m) are resolved on the shipped
# 64 x 64 grid: the narrowest fold of 2 s is 5 grid spacings on FD 64 x 64, 3.75 on FE 32 x 32 elements. The silky
# curtain's fold scale (0.050 m) spans 3 spacings, its median fold 6.6 (FD) and 4.5 (FE), narrowing to 1-2 next to
# the drawn end, where the gathered cloth stacks (docs/design.md, Findings). A limp cloth (xi = 1e-5) folds at the
# grid scale on every grid tried, up to FD 96 x 96 nodes.
_CURTAIN = dict(size=(1.0, 1.2), mu=0.2, gamma=0.2, eta=20.0, xi=1e-4, nodes=(64, 64))
_SILKY = dict(_CURTAIN, scale=20.0)
# Contact scenes: the same cloth, with friction 0.3 against the obstacles and a barrier active within 1 mm
_CLOTH = dict(mu=0.2, gamma=0.1, eta=20.0, xi=1e-5, contact=Contact(distance=1e-3, friction=0.3))
# The drape's cloth is a stiff fabric (bending length (2 xi / (mu g))^(1/3) = 6.7 cm): its folds are resolved on
# the study's quick grids; the limp cloth's (xi = 1e-5) fold at about 3 cm (fold_wavelength) and are not
_DRAPE_XI = 3e-4
# The cloth leaves the table at its rim: contact points only at the nodes (FD) or at h / 2 (FE) support it only where
# one lands on the table, and the surface between them cuts the rim, a support radius short by up to their spacing
# (FD 9, 17, 33 nodes: drape coefficient 0.885, 0.898, 0.923). Four contact points per cell side: 0.923, 0.924, 0.924.
_DRAPE_CONTACT = Contact(distance=1e-3, friction=0.3, samples=4)
SCENES: dict[str, SceneSpec] = {}
for _spec in (
    SceneSpec("hanging", HangingConfig, dict(size=(1.0, 1.0), mu=0.2, gamma=0.05, eta=50.0, xi=1e-5), _hanging,
              "cloth pinned at its two top corners, falling under gravity"),
    SceneSpec("curtain", CurtainConfig, _CURTAIN, _curtain,
              "curtain drawn open along its rod, folding by itself (Figs 3-4)"),
    SceneSpec("curtain-silky", CurtainConfig, _SILKY, _curtain,
              "the curtain with mu, gamma, f scaled by 20 (Fig. 5)"),
    SceneSpec("paper", CurtainConfig, dict(_SILKY, xi=16 * _CURTAIN["xi"]), _curtain,
              "the silky curtain with 16 times the curvature resistance (Fig. 6)"),
    SceneSpec("flag", FlagConfig, dict(size=(1.2, 0.8), mu=0.2, gamma=0.05, eta=20.0, xi=1e-5), _flag,
              "flag on a pole, a coil on its free side, in the wind (Figs 7-8)"),
    SceneSpec("floor", FloorConfig, dict(_CLOTH, t_end=1.0), _floor,
              "cloth falling flat onto the floor and settling (contact)"),
    SceneSpec("sphere", SphereConfig, dict(_CLOTH, t_end=1.5), _sphere,
              "square cloth dropped onto a ball (contact)"),
    SceneSpec("drape", DrapeConfig, dict(_CLOTH, size=(0.3, 0.3), nodes=(33, 33), gamma=1.0, xi=_DRAPE_XI, t_end=1.5,
                                         contact=_DRAPE_CONTACT),
              _drape,
              "the Cusick drape test on a round table, with its drape coefficient (contact)"),
):
    SCENES[_spec.name] = _spec


def config(name: str, **fields_) -> SceneConfig:
    """The config of the named scene with some fields overridden.

    Raises
    ------
    ValueError
        Unknown scene name, unknown field, or a bad value (the message names it).
    """
    if name not in SCENES:
        raise InputError(f"unknown scene {name!r}; known scenes: {', '.join(SCENES)}")
    return SCENES[name].config(**fields_)


def build(cfg: SceneConfig) -> Scene:
    """The Scene of a config."""
    return SCENES[cfg.scene].builder(cfg)


def hanging(nodes=None, **fields_) -> Scene:
    """Cloth pinned at two top corners, falling from horizontal under gravity.

    1 m x 1 m, mu = 0.2 kg/m^2, gamma = 0.05 kg/(m^2 s), eta = 50 N/m,
    xi = 1e-5 N m, full tensors, scale 1 (real-world values, section 4).
    """
    return SCENES["hanging"](nodes, **fields_)


def curtain(nodes=None, **fields_) -> Scene:
    """The opening curtain of Figs 3-4 (see the module docstring for the mechanism and the differences).

    1 m wide, 1.2 m tall, mu = 0.2 kg/m^2, gamma = 0.2 kg/(m^2 s), eta = 20
    N/m, xi = 1e-4 N m, full tensors, scale 1, on 64 x 64 nodes (its folds
    at least 3 grid spacings wide); the rod end drawn 0.6 m over 1.6 s; 2 s
    of motion at dt = 5 ms (implicit Euler).
    """
    return SCENES["curtain"](nodes, **fields_)


def curtain_silky(nodes=None, **fields_) -> Scene:
    """Fig. 5: the curtain with mu, gamma and the forces scaled by 20 (section 3.1), on 64 x 64 nodes.

    Relative to its weight the sheet is 20 times softer in stretching and in
    bending: folds about 20^(1/4) = 2.1 times narrower than the curtain's.
    """
    return SCENES["curtain-silky"](nodes, **fields_)


def paper(nodes=None, **fields_) -> Scene:
    """Fig. 6: the silky curtain with xi = 1.6e-3 N m (16 times), folds twice as wide.

    The paper's xi = 3e-6 N m is a different material here (module docstring).
    """
    return SCENES["paper"](nodes, **fields_)


def flag(nodes=None, **fields_) -> Scene:
    """The flag of Figs 7-8: pole edge pinned, coils on the free corners, wind along the flag.

    1.2 m x 0.8 m in the vertical x-z plane, pole along a1 = 0. mu = 0.2
    kg/m^2, gamma = 0.05 kg/(m^2 s), eta = 20 N/m, xi = 1e-5 N m, scale 1.
    Coils of 30 N/m to anchors 0.1 m beyond the free corners, swinging 0.15 m
    across the flag at 6 Hz; wind 10 m/s along the flag (c = 0.6 kg/m^3).
    """
    return SCENES["flag"](nodes, **fields_)


def floor(nodes=None, **fields_) -> Scene:
    """A 1 m cloth falling flat from 0.3 m onto the floor and settling (friction 0.3, barrier within 1 mm)."""
    return SCENES["floor"](nodes, **fields_)


def sphere(nodes=None, **fields_) -> Scene:
    """A 1 m cloth dropped from 5 cm above onto a ball of radius 0.25 m (friction 0.3)."""
    return SCENES["sphere"](nodes, **fields_)


def drape(nodes=None, **fields_) -> Scene:
    """The Cusick drape test: a 0.3 m square cloth on a round table 0.18 m across (module docstring)."""
    return SCENES["drape"](nodes, **fields_)


# -- scene files -----------------------------------------------------------------
def read_toml(path, **overrides) -> SceneConfig:
    """A scene config from a TOML file: ``scene = "curtain"`` plus fields to override.

    Parameters
    ----------
    path : str or Path
        The file. Keys are the fields of the scene's config (see
        :class:`SceneConfig` and its subclasses); ``size``, ``nodes`` and
        ``rest_metric`` are two-element arrays.
    **overrides
        Applied after the file (command-line values).

    Raises
    ------
    ValueError
        Unreadable or malformed file, missing or unknown ``scene``, an unknown key
        (named in the message), or a bad value.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as err:
        raise InputError(f"cannot read scene file {str(path)!r}: {getattr(err, 'strerror', None) or err}") from None
    return read_toml_text(text, source=str(path), **overrides)


def read_toml_text(text: str, source: str = "<string>", **overrides) -> SceneConfig:
    """Like :func:`read_toml`, from TOML text; ``source`` names it in error messages."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"scene file {source!r} is not valid TOML: {err}") from None
    if "scene" not in data:
        raise InputError(f"scene file {source!r} must name its scene, e.g. scene = \"curtain\"")
    name = data.pop("scene")
    table = data.pop("run", None)  # the command's settings (run_table), not scene fields
    if table is not None and not isinstance(table, dict):
        raise InputError(f"scene file {source!r}: run must be a table [run], got {table!r}")
    if not isinstance(name, str):
        raise InputError(f"scene file {source!r}: scene must be a name, got {name!r}")
    spec = SCENES.get(name)
    if spec is None:
        raise InputError(f"unknown scene {name!r} in {source!r}; known scenes: {', '.join(SCENES)}")
    known = {f.name for f in fields(spec.config_class)}
    for key in data:
        if key not in known:
            raise InputError(f"unknown key {key!r} in scene file {source!r}; known keys: {', '.join(sorted(known))}")
    return spec.config(**{**data, **overrides})  # the command line wins over the file


def run_table(text: str, source: str = "<string>") -> dict:
    """The ``[run]`` table of a resolved config (backend, scheme, version, ...; empty when there is none).

    :func:`to_toml` writes it with ``run=``; the scene readers skip it, ``deformable run`` reads it.
    """
    try:
        table = tomllib.loads(text).get("run", {})
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"scene file {source!r} is not valid TOML: {err}") from None
    if not isinstance(table, dict):
        raise InputError(f"scene file {source!r}: run must be a table [run], got {table!r}")
    return table


def _toml_value(value) -> str:
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def to_toml(cfg: SceneConfig, run: dict | None = None) -> str:
    """The resolved config as TOML text that :func:`read_toml` reads back to an equal config.

    The contact settings follow as a ``[contact]`` table and the extra obstacles as ``[[obstacles]]`` tables;
    ``run``: settings that are not scene fields (backend, scheme, package version, ...), written as a
    ``[run]`` table after them (:func:`run_table` reads it back).
    """
    lines = [f"# resolved scene config ({SCENES[cfg.scene].summary})"]
    for f in fields(cfg):
        if f.name not in ("obstacles", "contact"):
            lines.append(f"{f.name} = {_toml_value(getattr(cfg, f.name))}")
    tables = ([("[contact]", cfg.contact.table())] if cfg.contact is not None else []) + [
        ("[[obstacles]]", o.table()) for o in cfg.obstacles]
    if run:
        tables.append(("[run]", {k: v for k, v in run.items() if v is not None}))
    for head, table in tables:
        lines += ["", head] + [f"{k} = {_toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"
