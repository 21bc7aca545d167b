r"""What every scene's config has: :class:`SceneConfig`, the registered base of the catalogue (its fields, checks,
material and the section 3.1 scaling).

A config is a frozen dataclass of plain numbers (SI units) whose defaults are
the scene's values; a scene of the catalogue is one subclass with a ``name``
(the project's registry, :mod:`deformable.registry`) that adds its fields or
changes their defaults and builds its :class:`~deformable.scene.Scene`
(:mod:`.cloth`, :mod:`.curtain`, :mod:`.flag`, :mod:`.contact`). A config
written by a user's own module registers in the same way and is then
accepted by name wherever a scene is (scene files, ``deformable run``).

Macro control (section 3.1): ``scale`` multiplies mu, gamma and the applied
forces while eta and xi stay (:meth:`SceneConfig.scaling`); mu and gamma are
the real-world values before scaling, so a scene file states the physics and
its scaling apart, as section 4 recommends.
"""

import dataclasses
import math
from dataclasses import dataclass, fields
from typing import ClassVar

import numpy as np

from ..checks import is_real, known_keys, suggest
from ..contact.obstacles import Obstacle
from ..contact.obstacles import from_table as obstacle_from_table
from ..contact.settings import Contact
from ..dynamics.stepper import DT_MIN
from ..errors import InputError
from ..physics.force_models import ForceModel
from ..physics.material import Material
from ..registry import Registered
from ..scene.scene import Scene
from .rest_shapes import from_table as rest_shape_from_table

__all__ = ["SceneConfig", "force_model_field", "force_model_table"]


def force_model_field(value, where: str = "scene field force_model"):
    """A config's force model: a registered name, kept as it is; a ``[force_model]`` table, its ``kind`` the name
    and beside it the model's own fields (Koiter's E, nu, h), as obstacles are [[obstacles]] tables: the name
    when there are none, else the model built from them; a ForceModel, its name when it has no parameters.
    InputError naming the field (``force_model``, ``force_model.kind`` or the unknown key) and the known names."""
    names = ", ".join(ForceModel.names())
    if isinstance(value, ForceModel):
        return value.name if value == value.name else value
    if isinstance(value, str):
        if value not in ForceModel.names():
            raise InputError(f"{where} must be one of {names}, got {value!r}{suggest(value, ForceModel.names())}",
                             field="force_model", value=value)
        return value
    if not isinstance(value, dict):
        raise InputError(f"{where} must be a name ({names}) or a [force_model] table with a kind, got {value!r}",
                         field="force_model", value=value)
    table = dict(value)
    kind = table.pop("kind", None)
    if not isinstance(kind, str) or kind not in ForceModel.names():
        raise InputError(f"{where}.kind must be one of {names}, got {kind!r}{suggest(kind, ForceModel.names())}",
                         field="force_model.kind", value=kind)
    cls = ForceModel.lookup(kind)
    own = [f.name for f in fields(cls)] if dataclasses.is_dataclass(cls) else []
    known_keys(table, ["kind", *own], f"in {where} of kind {kind!r}",
               field=next((f"force_model.{k}" for k in table if k not in own), None))
    return cls(**table) if table else kind


def force_model_table(value):
    """What a scene file writes of a config's force model: its name, or for a model with parameters its
    ``[force_model]`` table (``kind`` and its fields), which :func:`force_model_field` reads back to an equal model."""
    if isinstance(value, str):
        return value
    return {"kind": value.name, **{f.name: getattr(value, f.name) for f in fields(value)}}


@dataclass(frozen=True, kw_only=True)
class SceneConfig(Registered, family="scene"):
    """Fields every scene has (SI units); a subclass with a ``name`` is a scene of the catalogue.

    A scene is one subclass: its ``name`` and ``summary``, the fields it adds or whose defaults it changes,
    and :meth:`build`, which turns the config into a :class:`~deformable.scene.Scene`. The registry name is
    also :attr:`scene` (the first key of a scene file).

    Parameters
    ----------
    size : (L1, L2)
        Sheet size, the parameter rectangle, metres at rest (m).
    nodes : (M, N)
        Node grid, nodes along a1 and a2 (1).
    mu : float
        Real-world mass density (kg/m^2). The scene uses ``scale * mu``.
    gamma : float
        Real-world damping density (kg/(m^2 s)). The scene uses ``scale * gamma``.
    eta : float
        Stretching weight of eq. (13), eta_11 = eta_22 = eta (N/m).
    xi : float
        Bending weight of eq. (13), xi_11 = xi_22 = xi (N m).
    shear : float
        Cross weights eta_12 = shear eta, xi_12 = shear xi; 1 isotropic, the paper 0 (1). 1 is the
        isotropic sheet with Poisson ratio 0.
    g : float
        Gravity; the force mu g scales with mu (m/s^2).
    scale : float
        Section 3.1 factor on mu, gamma and the applied forces (1). See :meth:`scaling`.
    dt : float
        Default time step (s).
    t_end : float
        Default simulated time (s).
    force_model : str or ForceModel
        Force model: variational (default), tpbf87, frozen or another registered one, by name or as a
        ``[force_model]`` table, its ``kind`` and the model's own fields (``kind = "koiter"``, E, nu, h) (-).
        See :class:`deformable.ForceModel` and :func:`force_model_field`.
    alpha : float
        The frozen model's stretching weight, alpha_11 = alpha_22, alpha_12 = 0 (N/m). Given directly
        (section 3.2); a cross weight of r_1 . r_2 would make the membrane energy indefinite. The frozen
        model needs alpha or beta positive; the other models take eta and xi, and refuse alpha and beta.
    beta : float
        The frozen model's bending weight, beta_11 = beta_22, beta_12 = shear beta (N m).
    rest_metric : (G0_11, G0_22)
        Rest metric G0 = diag(G0_11, G0_22); (1, 1) is flat (1). A value below 1 prestresses the
        sheet: it is in tension until its fibres shrink to sqrt(G0_ii) of their length.
    rest_curvature : (B0_11, B0_22)
        Rest curvature B0 = diag(B0_11, B0_22); (0, 0) is flat (1/m). (1 / R, 0) is a cylinder of
        radius R along a2, a sheet that curls back into it; both non-zero on a flat metric is no surface
        at all (eq. (10): ``deformable check`` says so, and the Scene warns).
    rest_shape : dict or None
        A named rest surface instead of rest_metric and rest_curvature (-). :mod:`.rest_shapes`:
        ``{kind = "sphere", radius = 2.0}``, "cylinder", "saddle", or "height" with a grid of heights z;
        its G0 and B0 as the rest metric and curvature; exclusive with ``rest_metric`` and
        ``rest_curvature``.
    obstacles : tuple of Obstacle
        Obstacles besides the scene's own, [[obstacles]] tables in a scene file (-).
    contact : Contact or None
        How the sheet meets the obstacles, a [contact] table; None: Contact() (-).
    fabric : str
        A named fabric (``deformable fabrics``; :meth:`deformable.Fabric.preset`), its warp along a1; "" none (-).
        Its areal density is mu and its warp and weft weights under the force model replace eta, xi and shear
        (:meth:`deformable.Fabric.weights`; the fields mu, eta and xi then show its density and its warp's
        weights); ``scale`` scales it as it scales any sheet. Exclusive with mu, eta, xi and shear.
    """

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
    force_model: str | ForceModel = "variational"
    alpha: float = 0.0
    beta: float = 0.0
    rest_metric: tuple = (1.0, 1.0)
    rest_curvature: tuple = (0.0, 0.0)
    rest_shape: dict | None = None
    obstacles: tuple = ()
    contact: Contact | None = None
    fabric: str = ""
    #: fields that must be positive, and non-negative (subclasses add theirs)
    POSITIVE: ClassVar[tuple] = ("dt", "t_end", "mu", "scale")
    NON_NEGATIVE: ClassVar[tuple] = ("gamma", "eta", "xi", "alpha", "beta")

    #: the registry's one line on the scene (scene files, listings)
    summary: ClassVar[str] = ""

    @property
    def scene(self) -> str:
        """The scene's registry name."""
        return self.name

    def build(self) -> Scene:
        """The Scene of this config."""
        raise NotImplementedError

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "obstacles":
                if not isinstance(value, (dict, Obstacle, list, tuple)):
                    raise InputError(f"scene field obstacles must be [[obstacles]] tables (or obstacles), got "
                                     f"{value!r}", field="obstacles", value=value)
                tables = [value] if isinstance(value, (dict, Obstacle)) else list(value)
                object.__setattr__(self, f.name, tuple(obstacle_from_table(t, f"scene field obstacles[{k}]")
                                                       for k, t in enumerate(tables)))
            elif f.name == "rest_shape":
                continue  # checked below, once size is
            elif f.name == "fabric":
                continue  # below, once force_model is checked
            elif f.name == "contact":
                if value is not None:
                    object.__setattr__(self, f.name, Contact.from_table(value, "scene field contact"))
            elif f.name == "force_model":
                object.__setattr__(self, f.name, force_model_field(value))
            elif f.name in ("size", "nodes", "rest_metric", "rest_curvature"):
                kind = int if f.name == "nodes" else float
                try:
                    pair = tuple(value)
                    ok = len(pair) == 2 and all(
                        is_real(v) and math.isfinite(v) and kind(v) == v
                        for v in pair
                    )
                except TypeError:
                    ok = False
                if not ok:
                    raise InputError(f"scene field {f.name} must be two {kind.__name__}s, got {value!r}")
                object.__setattr__(self, f.name, tuple(kind(v) for v in pair))
            elif f.type in (int, "int"):
                if not is_real(value) or not math.isfinite(value) or int(value) != value:
                    raise InputError(f"scene field {f.name} must be an integer, got {value!r}")
                object.__setattr__(self, f.name, int(value))
            else:
                if not is_real(value) or not math.isfinite(value):
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
        if self.rest_shape is not None:
            if self.rest_metric != (1.0, 1.0) or self.rest_curvature != (0.0, 0.0):
                raise InputError("scene field rest_shape names the rest surface; it cannot be given with rest_metric "
                                 "or rest_curvature", field="rest_shape", value=self.rest_shape)
            object.__setattr__(self, "rest_shape", rest_shape_from_table(self.rest_shape, self.size).table)
        if self.fabric != "":
            self._take_fabric()
        direct = self._weights_given()
        if direct and not (self.alpha > 0 or self.beta > 0):
            raise InputError(f"scene fields alpha and beta: the {self.force_model} force model needs alpha > 0 or "
                             "beta > 0 (its weights, given directly; e.g. alpha=1 beta=1e-3)", field="alpha",
                             value=self.alpha)
        if not direct and (self.alpha or self.beta):
            raise InputError(f"scene fields alpha = {self.alpha!r}, beta = {self.beta!r} are the frozen model's "
                             f"weights; the {self.force_model} model takes eta and xi (set force_model = \"frozen\")",
                             field="alpha", value=self.alpha)

    #: the fields a named fabric sets (:attr:`fabric`)
    FABRIC_FIELDS: ClassVar[tuple] = ("mu", "eta", "xi", "shear")

    @classmethod
    def stated(cls, values: dict) -> dict:
        """Config fields ``values`` (name -> value) as a scene file or a sweep case states them: with a named
        ``fabric`` among them, without the :data:`FABRIC_FIELDS` it sets (the fabric stands for them; given beside
        it they clash)."""
        if not values.get("fabric"):
            return dict(values)
        return {k: v for k, v in values.items() if k not in cls.FABRIC_FIELDS}

    def _take_fabric(self) -> None:
        """mu, eta, xi and shear from the named fabric: its density, its warp's weights and its shear over the
        warp's stretching (for display; :meth:`material` takes its full tensors)."""
        if not isinstance(self.fabric, str):
            raise InputError(f"scene field fabric must be a fabric's name, got {self.fabric!r}", field="fabric",
                             value=self.fabric)
        if self._weights_given():
            raise InputError(f"scene field fabric: the {self.force_model} model takes its weights alpha and beta "
                             "directly, not a fabric's", field="fabric", value=self.fabric)
        fabric = self.named_fabric()
        eta, xi = fabric.weights(self.force_model)
        for name, value in (("mu", fabric.density), ("eta", eta[0, 0]), ("xi", xi[0, 0]),
                            ("shear", min(1.0, eta[0, 1] / eta[0, 0]))):
            object.__setattr__(self, name, float(value))

    def named_fabric(self):
        """The :class:`deformable.Fabric` of :attr:`fabric` (None without one)."""
        from ..physics.fabric import Fabric

        return Fabric.preset(self.fabric) if self.fabric else None

    def _weights_given(self) -> bool:
        """The force model takes its weights as alpha and beta, given directly (the frozen model, section 3.2)."""
        return ForceModel.of(self.force_model).weights == ("alpha", "beta")

    def with_obstacles(self, *own: Obstacle) -> dict:
        """:meth:`scene_kwargs` with the scene's own obstacles before the config's extra ones."""
        kwargs = self.scene_kwargs()
        kwargs["obstacles"] = own + tuple(self.obstacles)
        return kwargs

    def scene_kwargs(self) -> dict:
        """Keyword arguments of Scene common to every scene (force model, rest metric and curvature, name)."""
        G0 = None if self.rest_metric == (1.0, 1.0) else np.diag(self.rest_metric)
        B0 = None if self.rest_curvature == (0.0, 0.0) else np.diag(self.rest_curvature)
        if self.rest_shape is not None:
            patch = rest_shape_from_table(self.rest_shape, self.size)
            G0, B0 = patch.metric, patch.curvature
        return dict(force_model=self.force_model, rest_metric=G0, rest_curvature=B0, name=self.scene,
                    obstacles=self.obstacles, contact=self.contact)

    def replace(self, **changes) -> "SceneConfig":
        """A copy with some fields changed; an unknown field is a ValueError naming it."""
        known_keys(changes, sorted(f.name for f in fields(self)), f"for scene {self.scene!r}")
        fabric = changes.get("fabric", self.fabric)
        clash = sorted(set(changes) & set(self.FABRIC_FIELDS))
        if fabric and clash:
            raise InputError(f"scene fields {', '.join(clash)} and fabric = {fabric!r}: the fabric sets mu, eta, xi "
                             f"and shear; give one or the other (fabric=\"\" drops it)", field=clash[0],
                             value=changes[clash[0]])
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
        if self.fabric:  # the fabric's full tensors, warp and weft (the scalar fields show its warp's)
            eta, xi = self.named_fabric().weights(self.force_model)
            return Material(mu=self.scale * self.mu, gamma=self.scale * self.gamma, eta=eta, xi=xi)
        return Material(mu=self.scale * self.mu, gamma=self.scale * self.gamma, eta=tensor(self.eta),
                        xi=tensor(self.xi), **frozen)

    def scaling(self) -> str:
        """What ``scale`` does, in words (section 3.1)."""
        if self.scale == 1:
            return "scale 1: mu, gamma and the forces are the real-world values"
        return (f"scale {self.scale:g}: mu, gamma and the applied forces are {self.scale:g} times the real-world "
                f"values while eta and xi stay, so the sheet moves as the real one would with eta = "
                f"{self.eta / self.scale:.4g} N/m and xi = {self.xi / self.scale:.4g} N m (section 3.1)")
