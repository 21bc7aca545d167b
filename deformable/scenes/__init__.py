r"""The catalogue: the paper's example scenes (section 5), in SI units, and scene files (TOML).

Every scene is a frozen *config* of plain numbers (a dataclass whose defaults
are the scene's values), one registered subclass of
:class:`~deformable.scenes.config.SceneConfig` that builds its
:class:`~deformable.scene.Scene`. The view :data:`SCENES` maps a name to a
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
times in bending, than the paper's (:func:`~deformable.scenes.scaling.equivalent_weights` maps them).

Macro control (section 3.1): ``scale`` multiplies mu, gamma and the applied
forces (gravity through mu, the curtain's push, the coils' stiffness, the
wind's drag) while eta and xi stay: the motion is then the one the unscaled
sheet would have with eta / scale and xi / scale, a relatively softer sheet
(:meth:`SceneConfig.scaling`). Equivalent weights between force models and
the folds' length scale: :mod:`.scaling`; the planes, the curtain's seeded
start and the smooth ramp: :mod:`.shapes`; scene files: :mod:`.files`. Each field's meaning and unit (its config class's docstring): :mod:`.fields`. The fields mu and gamma are the real-world
values before scaling, so a scene file states the physics and its scaling
apart, as section 4 recommends.

The scenes, each in its module with how it differs from the paper's text:
``hanging`` (:mod:`.cloth`), ``curtain``, ``curtain-silky``, ``paper``
(:mod:`.curtain`, Figs 3-6), ``flag`` (:mod:`.flag`, Figs 7-8), ``floor``,
``sphere``, ``drape`` (:mod:`.contact`), ``coil`` (:mod:`.strip`), ``panel``,
``panel-soft`` (:mod:`.panel`, section 3.2, Figs 1-2). A new scene
is one class: a subclass of :class:`~deformable.scenes.config.SceneConfig` with
a ``name``, its fields and ``build()`` (examples/custom_scene.py builds a Scene
directly instead).

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

from .cloth import HangingConfig
from .config import SceneConfig
from .contact import DrapeConfig, FloorConfig, SphereConfig
from .curtain import CurtainConfig, PaperConfig, SilkyCurtainConfig, hook_nodes
from .fields import FieldDoc, config_table, field_docs
from .files import read_toml, read_toml_text, run_table, to_toml
from .flag import FlagConfig
from .panel import PanelConfig, SoftPanelConfig
from .params import Parameter, Parameters, parameters
from .registry import (
    SCENES,
    SceneSpec,
    build,
    coil,
    config,
    curtain,
    curtain_silky,
    drape,
    flag,
    floor,
    hanging,
    panel,
    panel_soft,
    paper,
    sphere,
)
from .scaling import equivalent_weights, fold_wavelength
from .shapes import HORIZONTAL, VERTICAL, FoldNoise, smooth_ramp
from .strip import CoilConfig

__all__ = ["SCENES", "SceneSpec", "SceneConfig", "HangingConfig", "CurtainConfig", "SilkyCurtainConfig", "PaperConfig",
           "FlagConfig", "FloorConfig", "SphereConfig", "DrapeConfig", "CoilConfig", "config", "build", "read_toml",
           "read_toml_text", "to_toml", "run_table", "hanging", "curtain", "curtain_silky", "paper", "flag", "floor",
           "sphere", "drape", "coil", "equivalent_weights", "fold_wavelength", "parameters", "Parameters", "field_docs",
           "config_table", "FieldDoc", "Parameter", "smooth_ramp", "FoldNoise", "hook_nodes", "VERTICAL", "HORIZONTAL",
           "PanelConfig", "SoftPanelConfig", "panel", "panel_soft"]
