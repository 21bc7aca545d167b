r"""The paper's example scenes (section 5), in SI units, and scene files (TOML).

Every scene is a frozen *config* of plain numbers (a dataclass whose defaults
are the scene's values) and a builder that turns it into a
:class:`~deformable.scene.Scene`. The registry :data:`SCENES` maps a name to a
:class:`SceneSpec`; calling a spec, or the module-level function of the same
name, gives the Scene on a node grid::

    scene = scenes.curtain(nodes=(32, 32))             # a Scene
    cfg = scenes.config("curtain", eta=80.0)           # the config, overridden
    cfg = scenes.read_toml("my-curtain.toml")          # scene = "curtain" + fields
    scene = scenes.build(cfg)

Scenes (paper section 5; all with eta_11 = eta_22 = eta, xi_11 = xi_22 = xi,
eta_12 = xi_12 = 0 as in section 3.2):

``hanging``
    A square cloth, initially horizontal, pinned at its two top corners,
    falling and swinging under gravity.
``curtain``
    The opening curtain of Figs 3-4: the sheet hangs in the vertical x-z
    plane, its top row slides on a rail along x (``Slide("top", "x")``), the
    rail end at a1 = 0 is pinned. Forces perpendicular to the rest plane
    (along y, alternating in sign across the width, strongest on the upper
    part) push the sheet out of its plane into folds; the folded fibres, in
    tension, draw the rail nodes together (the rail gathers to about half its
    width in 2 s). The rail row hangs from rings: eta_11 = 0 on it, so being
    gathered costs it nothing.
``curtain-silky``
    Fig. 5: the same curtain with mu, gamma and the applied forces scaled up
    (the macro-control scaling of section 3.1), eta unchanged.
``paper``
    Fig. 6: the silky curtain with curvature resistance xi = 3e-6 N m.
``flag``
    Figs 7-8: the pole edge (a1 = 0) pinned, gravity, and a wind load on the
    sheet that varies in time: a steady push away from the pole plus a
    pressure wave across the sheet travelling from the pole to the free edge.

Scaling (section 3.1). Equation (11), ``mu r_tt + gamma r_t + e(r) = f``, gives
the same trajectory for (a mu, a gamma, a f) with the elastic weights scaled
by a as well; the macro-control triple (mu, gamma, f) may therefore be scaled
to a numerically convenient range while eta, xi fine-tune the shape
(micro-control, section 4). Each scene records its ``scale``: the factor
applied to the real-world mu, gamma and applied forces (gravity, being mu g,
scales with mu by itself).

Stability (docs/design.md, "Time stepping"). The tpbf87 step lags alpha_ij,
so it is only conditionally stable on stretching: dt must stay below about
``h sqrt(mu / (2 eta G))`` on FD (the backend's ``stable_step()``). Each
scene's default dt keeps a margin of at least 1.4 below the FD bound on its
default 32 x 32 grid, and a finer grid needs a proportionally smaller dt (the
command line warns, and picks FE's own, smaller, step).
Compression makes alpha < 0, a negative stiffness: with xi = 0 (and under
tpbf87 even with xi > 0, whose linear bending stiffness about a flat sheet is
zero) nothing resists grid-scale crumpling, and a compressed region collapses
into a crumpled ball within a fraction of a second (measured: a curtain whose
rail end was pulled along the rail, or a prestressed curtain left free to
contract, both did). The folding scenes are therefore built so that the sheet
stays in tension: the folds are *pushed* out of plane by the perpendicular
load over the whole height (fibres get longer, alpha > 0) and the rail is
drawn together by that tension, instead of the rail being pushed together
(which compresses the cloth below it). Measured at 32 x 32 over 2 s: G11 stays
above 0.86 in the curtain (0.75 in the silky one), G22 above 1. A run that
leaves these bounds is caught by the DivergenceGuard of the run command.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import tomllib
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Callable

import numpy as np

from .constraints import Pin, Slide
from .forces import BodyForce, Gravity
from .material import Material
from .scene import FORCE_MODELS, Scene
from .sheet import Plane, Sheet

__all__ = [
    "SCENES", "SceneSpec", "read_toml_text", "SceneConfig", "HangingConfig", "CurtainConfig", "FlagConfig", "Plane",
    "hanging", "curtain", "curtain_silky", "paper", "flag", "config", "build", "read_toml", "to_toml",
]

log = logging.getLogger(__name__)


# -- geometry ------------------------------------------------------------------
#: the vertical x-z plane: a1 along x, a2 up (the curtain and the flag hang in it)
VERTICAL = Plane(e1=(1.0, 0.0, 0.0), e2=(0.0, 0.0, 1.0))
#: the horizontal x-y plane (the default rest shape)
HORIZONTAL = Plane()


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
        Mass density in kg/m^2 (after scaling).
    gamma : float
        Damping density in kg/(m^2 s) (after scaling).
    eta, xi : float
        Stretching (N/m) and bending (N m) weights, eta_11 = eta_22, xi_11 = xi_22.
    g : float
        Gravity in m/s^2 (the force mu g scales with mu).
    scale : float
        The section 3.1 factor already applied to mu, gamma and the applied forces
        (recorded for the reader; changing it does not rescale the other fields).
    dt : float
        Default time step (s).
    t_end : float
        Default simulated time (s).
    force_model : str
        "tpbf87" (default) or another of :data:`deformable.FORCE_MODELS`.
    rest_metric : (G0_11, G0_22)
        The rest metric G0 = diag(G0_11, G0_22) (dimensionless); (1, 1) is the
        flat rest shape itself. A value below 1 prestresses the sheet: it is
        in tension until its fibres shrink to sqrt(G0_ii) of their length.
    """

    scene: str
    size: tuple = (1.0, 1.0)
    nodes: tuple = (32, 32)
    mu: float = 0.2
    gamma: float = 0.1
    eta: float = 50.0
    xi: float = 0.0
    g: float = 9.81
    scale: float = 1.0
    dt: float = 1e-3
    t_end: float = 2.0
    force_model: str = "tpbf87"
    rest_metric: tuple = (1.0, 1.0)

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "scene":
                if value not in SCENES:
                    raise ValueError(f"unknown scene {value!r}; known scenes: {', '.join(SCENES)}")
            elif f.name == "force_model":
                if value not in FORCE_MODELS:
                    raise ValueError(f"scene field force_model must be one of {FORCE_MODELS}, got {value!r}")
            elif f.name in ("size", "nodes", "rest_metric"):
                kind = int if f.name == "nodes" else float
                try:
                    pair = tuple(value)
                    ok = len(pair) == 2 and all(
                        not isinstance(v, bool) and isinstance(v, (int, float)) and kind(v) == v for v in pair
                    )
                except TypeError:
                    ok = False
                if not ok:
                    raise ValueError(f"scene field {f.name} must be two {kind.__name__}s, got {value!r}")
                object.__setattr__(self, f.name, tuple(kind(v) for v in pair))
            else:
                if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                    raise ValueError(f"scene field {f.name} must be a finite number, got {value!r}")
                object.__setattr__(self, f.name, float(value))
        for name in ("dt", "t_end", "mu"):
            if getattr(self, name) <= 0:
                raise ValueError(f"scene field {name} must be positive, got {getattr(self, name)!r}")
        if min(self.rest_metric) <= 0 or min(self.size) <= 0:
            raise ValueError(f"scene fields size and rest_metric must be positive, got {self.size!r}, {self.rest_metric!r}")

    def scene_kwargs(self) -> dict:
        """Keyword arguments of Scene common to every scene (force model, rest metric, name)."""
        G0 = None if self.rest_metric == (1.0, 1.0) else np.diag(self.rest_metric)
        return dict(force_model=self.force_model, rest_metric=G0, name=self.scene)

    def replace(self, **changes) -> SceneConfig:
        """A copy with some fields changed; an unknown field is a ValueError naming it."""
        known = {f.name for f in fields(self)}
        for key in changes:
            if key not in known:
                raise ValueError(f"unknown key {key!r} for scene {self.scene!r}; known keys: {', '.join(sorted(known))}")
        return dataclasses.replace(self, **changes)

    def material(self) -> Material:
        return Material(mu=self.mu, gamma=self.gamma, eta=self.eta, xi=self.xi)


@dataclass(frozen=True, kw_only=True)
class HangingConfig(SceneConfig):
    """A cloth pinned at its two top corners, starting horizontal (no extra fields)."""


@dataclass(frozen=True, kw_only=True)
class CurtainConfig(SceneConfig):
    """The opening curtain (Figs 3-5).

    Parameters
    ----------
    push : float
        Amplitude of the force density perpendicular to the rest plane (N/m^2),
        ``push sin(pi folds a1 / L1)`` along y on the upper part.
    folds : float
        Number of half-waves of the push across the width.
    taper : float
        The push at the hem as a fraction of the push at the rail (it varies
        linearly in between: the upper part is pushed hardest).
    """

    push: float = 1.0
    folds: float = 6.0
    taper: float = 0.5


@dataclass(frozen=True, kw_only=True)
class FlagConfig(SceneConfig):
    """The waving flag (Figs 7-8).

    Parameters
    ----------
    wind : float
        Steady wind force density along +x, away from the pole (N/m^2).
    gust : float
        Amplitude of the pressure wave along y (N/m^2).
    frequency : float
        Frequency of the pressure wave (Hz).
    wavelength : float
        Wavelength of the pressure wave along a1 (m); it travels away from the pole.
    """

    wind: float = 1.0
    gust: float = 1.0
    frequency: float = 1.0
    wavelength: float = 1.0


# -- builders ------------------------------------------------------------------
def _hanging(cfg: HangingConfig) -> Scene:
    sheet = Sheet(size=cfg.size, nodes=cfg.nodes, rest=HORIZONTAL)
    return Scene(sheet, cfg.material(), forces=[Gravity(cfg.g)], constraints=[Pin(["top-left", "top-right"])],
                 **cfg.scene_kwargs())


def _curtain(cfg: CurtainConfig) -> Scene:
    L1, L2 = cfg.size
    M, N = cfg.nodes
    sheet = Sheet(size=cfg.size, nodes=cfg.nodes, rest=VERTICAL)
    k = math.pi * cfg.folds / L1

    def push(a1, a2, t):
        fy = cfg.push * np.sin(k * a1) * (cfg.taper + (1.0 - cfg.taper) * a2 / L2)
        return np.stack([np.zeros_like(fy), fy, np.zeros_like(fy)], axis=-1)

    # the rail row hangs from rings: no resistance to being gathered (eta_11 = 0 there)
    eta = np.zeros((2, 2, M, N))
    eta[0, 0] = eta[1, 1] = cfg.eta
    eta[0, 0, :, -1] = 0.0
    material = Material(mu=cfg.mu, gamma=cfg.gamma, eta=eta, xi=cfg.xi)
    forces = [Gravity(cfg.g), BodyForce(push)]
    constraints = [Slide("top", "x"), Pin("top-left")]
    return Scene(sheet, material, forces=forces, constraints=constraints, **cfg.scene_kwargs())


def _flag(cfg: FlagConfig) -> Scene:
    sheet = Sheet(size=cfg.size, nodes=cfg.nodes, rest=VERTICAL)
    w = 2.0 * math.pi * cfg.frequency
    k = 2.0 * math.pi / cfg.wavelength

    def wind(a1, a2, t):
        fx = np.full(np.shape(a1), cfg.wind)
        fy = cfg.gust * np.sin(w * t - k * a1) * np.ones_like(a2)
        return np.stack([fx, fy, np.zeros_like(fx)], axis=-1)

    return Scene(sheet, cfg.material(), forces=[Gravity(cfg.g), BodyForce(wind)], constraints=[Pin("left")],
                 **cfg.scene_kwargs())


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

    def __call__(self, nodes=(32, 32), **fields_) -> Scene:
        return self.builder(self.config(nodes=tuple(nodes), **fields_))


# Real-world starting point (section 4): cloth of about 0.2 kg/m^2. The curtain
# and the flag keep scale 1; the silky curtain and the paper multiply mu, gamma
# and the push by 20, which raises the dt bound by sqrt(20) at the same eta.
_CURTAIN = dict(size=(1.0, 1.2), mu=0.2, gamma=0.5, eta=20.0, xi=0.0, push=3.0, folds=6.0, taper=0.5,
                dt=1e-3, t_end=2.0)
_SILKY = dict(_CURTAIN, mu=4.0, gamma=10.0, eta=100.0, push=60.0, scale=20.0, dt=2e-3)
SCENES: dict[str, SceneSpec] = {}
for _spec in (
    SceneSpec("hanging", HangingConfig,
              dict(size=(1.0, 1.0), mu=0.2, gamma=0.05, eta=50.0, dt=1e-3, t_end=2.0), _hanging,
              "cloth pinned at its two top corners, falling under gravity"),
    SceneSpec("curtain", CurtainConfig, _CURTAIN, _curtain,
              "curtain on a rail gathering into folds (Figs 3-4)"),
    SceneSpec("curtain-silky", CurtainConfig, _SILKY, _curtain,
              "the curtain with mu, gamma, f scaled by 20 (Fig. 5)"),
    SceneSpec("paper", CurtainConfig, dict(_SILKY, xi=3e-6), _curtain,
              "the silky curtain with xi = 3e-6 (Fig. 6)"),
    SceneSpec("flag", FlagConfig,
              dict(size=(1.2, 0.8), mu=0.2, gamma=0.1, eta=20.0, wind=6.0, gust=4.0, frequency=1.5,
                   wavelength=0.8, dt=1e-3, t_end=2.0), _flag,
              "flag on a pole waving in a time-varying wind (Figs 7-8)"),
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
        raise ValueError(f"unknown scene {name!r}; known scenes: {', '.join(SCENES)}")
    return SCENES[name].config(**fields_)


def build(cfg: SceneConfig) -> Scene:
    """The Scene of a config."""
    return SCENES[cfg.scene].builder(cfg)


def hanging(nodes=(32, 32), **fields_) -> Scene:
    """Cloth pinned at two top corners, falling from horizontal under gravity.

    1 m x 1 m, mu = 0.2 kg/m^2, gamma = 0.05 kg/(m^2 s), eta = 50 N/m, xi = 0,
    scale 1 (real-world values, section 4). Default dt = 1e-3 s against a
    stretching bound of 1.4e-3 s at 32 x 32 (``h sqrt(mu/(2 eta))``); gravity
    keeps the sheet in tension, so alpha >= 0 except in small wrinkles along
    the free hem (G11 >= 0.95 measured over 2 s), which stay bounded.
    """
    return SCENES["hanging"](nodes, **fields_)


def curtain(nodes=(32, 32), **fields_) -> Scene:
    """The opening curtain of Figs 3-4 (see the module docstring).

    1 m wide, 1.2 m tall, mu = 0.2 kg/m^2, gamma = 0.5 kg/(m^2 s), eta = 20 N/m,
    xi = 0 (section 5: "xi set to zero and eta reasonably high"), scale 1.
    Push: 3 N/m^2 along y times ``sin(6 pi a1 / L1)``, tapering linearly from
    the rail to half at the hem. Default dt = 1e-3 s against a stretching
    bound of 2.3e-3 s at 32 x 32 (2e-3 s diverged within 20 steps once the
    folds stretch the fibres to G11 ~ 1.8, which lowers the bound by sqrt(G)).
    The sheet stays in tension (module docstring).
    """
    return SCENES["curtain"](nodes, **fields_)


def curtain_silky(nodes=(32, 32), **fields_) -> Scene:
    """Fig. 5: the curtain with mu, gamma and the push scaled by 20 (section 3.1).

    mu = 4 kg/m^2, gamma = 10 kg/(m^2 s), push 60 N/m^2, eta = 100 N/m: the
    triple (mu, gamma, f) scaled by 20 (gamma by another 1.25 for a calmer
    drape) with eta only 5 times larger, so the sheet is relatively softer and
    flows. The scaling raises the stretching bound (4.6e-3 s at 32 x 32), so the
    default dt is 2e-3 s: half the steps of the plain curtain.
    """
    return SCENES["curtain-silky"](nodes, **fields_)


def paper(nodes=(32, 32), **fields_) -> Scene:
    """Fig. 6: the silky curtain with curvature resistance xi = 3e-6 N m.

    Under the tpbf87 force model a flat sheet with B0 = 0 has no linear bending
    stiffness (docs/design.md, "Three readings of the model"), so xi acts only at second order in the
    fold amplitude; the paper saw the same insensitivity for xi up to 1e-3.
    Same dt and stability margins as ``curtain-silky``.
    """
    return SCENES["paper"](nodes, **fields_)


def flag(nodes=(32, 32), **fields_) -> Scene:
    """The flag of Figs 7-8: pole edge pinned, a time-varying wind.

    1.2 m x 0.8 m in the vertical x-z plane, pole along a1 = 0. mu = 0.2
    kg/m^2, gamma = 0.1 kg/(m^2 s), eta = 20 N/m, scale 1. Wind: 6 N/m^2 along
    +x (three times the weight, so the flag flies) plus a pressure wave
    ``gust sin(2 pi f t - 2 pi a1 / wavelength)`` along y (4 N/m^2, 1.5 Hz,
    0.8 m). The steady wind keeps the flag in tension (G11 between 1.01 and
    1.36 measured over 2 s), and dt = 1e-3 s is below the stretching bound of
    1.8e-3 s at 32 x 32 (eta = 40 with dt = 2e-3 diverged within 25 steps).
    """
    return SCENES["flag"](nodes, **fields_)


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
        raise ValueError(f"cannot read scene file {str(path)!r}: {getattr(err, 'strerror', None) or err}") from None
    return read_toml_text(text, source=str(path), **overrides)


def read_toml_text(text: str, source: str = "<string>", **overrides) -> SceneConfig:
    """Like :func:`read_toml`, from TOML text; ``source`` names it in error messages."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise ValueError(f"scene file {source!r} is not valid TOML: {err}") from None
    if "scene" not in data:
        raise ValueError(f"scene file {source!r} must name its scene, e.g. scene = \"curtain\"")
    name = data.pop("scene")
    if not isinstance(name, str):
        raise ValueError(f"scene file {source!r}: scene must be a name, got {name!r}")
    spec = SCENES.get(name)
    if spec is None:
        raise ValueError(f"unknown scene {name!r} in {source!r}; known scenes: {', '.join(SCENES)}")
    known = {f.name for f in fields(spec.config_class)}
    for key in data:
        if key not in known:
            raise ValueError(f"unknown key {key!r} in scene file {source!r}; known keys: {', '.join(sorted(known))}")
    return spec.config(**data, **overrides)


def _toml_value(value) -> str:
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def to_toml(cfg: SceneConfig) -> str:
    """The resolved config as TOML text that :func:`read_toml` reads back to an equal config."""
    lines = [f"# resolved scene config ({SCENES[cfg.scene].summary})"]
    for f in fields(cfg):
        lines.append(f"{f.name} = {_toml_value(getattr(cfg, f.name))}")
    return "\n".join(lines) + "\n"
