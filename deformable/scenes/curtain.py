r"""The opening curtain of Figs 3-6: the curtain (Figs 3-4), the silky curtain (Fig. 5) and paper (Fig. 6).

The curtain hangs in the vertical x-z plane. Its top row keeps its height
on the rod and slides along it (``Slide("top", ("x", "y"))``: rings slide
along x and swing out along y); the rod end at a1 = 0 is pinned and the
other end is drawn along the rod (a prescribed motion, a smooth ramp over
``draw_time``), gathering the top to ``1 - gather`` of its width. The cloth
below, compressed across, folds by itself: nothing in the loads selects a
wavelength. A small seeded perturbation of the flat start (``noise``, white
over the wavelengths 2 L1 / 32 .. 2 L1 along the width,
:class:`~deformable.scenes.shapes.FoldNoise`) decides which way each fold
goes, identically on every grid and backend. The fold width then follows
from the material, the bending length of a sheet held by its weight
(:func:`deformable.scenes.scaling.fold_wavelength`).

Real-world starting points (section 4): each of the three is a named fabric (``deformable fabrics``,
:meth:`deformable.Fabric.preset`), its warp along the width a1, on the grid that resolves its folds (below).
``curtain`` is denim (Wang, O'Brien and Ramamoorthi 2011: 324 g/m^2, tensile stiffness 411 / 2028 N/m and
bending rigidity 97 / 64 micro N m warp / weft, bending lengths 3.1 / 2.7 cm); ``curtain-silky`` the
lightest measured fabric, jacket-polyester (113 g/m^2, 86 / 343 N/m, 20 / 14 micro N m, 2.6 / 2.3 cm);
``paper`` ARCSim's estimate for paper (100 g/m^2, 1e6 N/m, 400 micro N m, 7.4 cm; an estimate, not a
measurement), stiffer in stretching and bending than every fabric preset. The paper's scaling recipe (section
3.1: mu, gamma, f scaled, eta and xi with them) serves its semi-implicit scheme, whose stable step it raises;
the implicit step here has no stability bound in eta or xi, so the scenes run at the real-world values
(``scale = 1``). ``fabric=""`` drops the fabric and keeps its warp's values as the isotropic fields mu, eta and
xi; the curtain before the fabrics, a bending length of 4.7 cm, stiffer than every measured fabric, is
``fabric="" mu=0.2 eta=20 xi=1e-4 shear=1``. A limp cloth (that with ``xi=1e-5``) folds at the grid scale on
FD 48 x 48 (its narrowest late fold 1 h); on 80 x 80, where its fold scale spans 4.7 spacings, the narrowest
fold of its last 0.4 s is 5 h (6.3 cm), while its first folds, during the draw, still narrow to 1 h
(:mod:`deformable.scenes.params`).

Differences from the paper: its curtain is folded by "external forces
perpendicular to the plane on the upper part" and its top restricted "to
the axis where it should slide"; here the top is drawn and may swing out of
the rod's line (held on a line, every top node would be a hinge at y = 0
and folds would start at grid scale under the rod). The paper's
perpendicular push stays available (``push``; ``folds > 0`` gives it the
earlier sin pattern, which selects the number of folds). ``rings = 1``
carries the top on hooks drawn together uniformly instead (``hooks`` their
spacing): an experiment that folds at the grid scale at the quick grids
(docs/design.md, "Findings").

Self-contact. Under the variational model (the default) the curtain's folds
keep clear of each other: with no ``contact`` of its own, the scene takes
:data:`SELF_CONTACT`, a barrier within 4 mm beyond a fabric 1 mm thick
(:mod:`deformable.contact.selfpotential`), so no two fold faces come closer
than 1 mm. Measured on FD 64 x 64 nodes over the 2 s (the curtain of issue 44,
before it was denim): without it the gathered folds next to the drawn end
passed through each other in 225 of its 400 steps; with it in none of 511
(steps the drawn end would have pressed through the folds are retried
shorter), the closest two faces 2.0 mm apart, in 127 s against 77 s wall time
(two runs side by side on two cores).
The paper's force (``force_model = "tpbf87"``, the semi-implicit scheme) has
no self-contact.

The grid for a named fabric. A curtain given a ``fabric`` and no ``nodes`` ships on the grid
that resolves that fabric's folds (:meth:`CurtainConfig.shipped_nodes`): the coarsest of
:data:`FABRIC_GRIDS` on which ``deformable params`` predicts the narrowest fold at least 3 grid
spacings wide (:attr:`deformable.scenes.params.Parameters.resolved`: the fold scale
(D H / (mu g))^(1/4) of the fabric's warp, Cerda and Mahadevan 2003, at least 4.5 grid spacings,
as measured on this scene): denim 64 x 64, jacket-polyester 80 x 80, paper 48 x 48. Measured with
``deformable run curtain fabric=NAME`` on the grid it picks (FD, 2 s, one thread; the paper study's fold
measure on the written frames every 0.1 s; docs/design.md, Findings): denim's narrowest late fold 5 h =
7.9 cm (167 s CPU); jacket-polyester's 9 h = 11.4 cm (334 s; on 64 x 64 a ridge kinked at the grid scale,
1 h). An explicit ``nodes`` (``--grid``, a scene file's) wins.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..contact.settings import Contact
from ..errors import InputError
from ..geometry.sheet import Sheet
from ..physics.forces import BodyForce, Gravity
from ..scene.constraints import Pin, Slide
from ..scene.scene import Scene
from .config import SceneConfig
from .params import fold_scale, resolving_nodes
from .shapes import VERTICAL, FoldNoise, smooth_ramp

__all__ = ["CurtainConfig", "SilkyCurtainConfig", "PaperConfig", "hook_nodes", "SELF_CONTACT", "FABRIC_GRIDS"]

#: the curtains' self-contact under the variational model: a barrier within 4 mm beyond a fabric 1 mm thick
SELF_CONTACT = Contact(self_distance=4e-3, thickness=1e-3)
#: the square FD grids (nodes a side) a curtain in a named fabric may ship on, coarsest first: multiples of 16 from
#: the coarsest grid the fold campaign saw resolved by the rule (48: xi = 1e-4, its narrowest fold 5 h) up to 192
FABRIC_GRIDS = tuple(range(48, 193, 16))


@dataclass(frozen=True, kw_only=True)
class CurtainConfig(SceneConfig):
    """The opening curtain (Figs 3-6).

    Parameters
    ----------
    gather : float
        How far the drawn end of the rod travels, a fraction of the width (1). 0.6: the top gathers to
        40 % of it; 0 leaves the top in place.
    draw_time : float
        Time over which the top is drawn, a smooth ramp (s). See :func:`smooth_ramp`.
    rings : int
        0: the top slides on the rod, its end drawn; 1: hooks on rings drawn together (-).
        With 1 the top hangs from hooks on rings that are drawn together uniformly, each hook at a1
        carried to x = a1 (1 - gather ramp), holding its height, free to swing along y; the top between
        hooks slides in the rod's plane. An experiment (issue 13): at the quick grids it folds at the grid
        scale (docs/design.md, "Findings").
    hooks : float
        With rings = 1, the hooks' spacing along the top; 0: a hook at every top node (m). Rounded to
        whole grid spacings (:func:`hook_nodes`).
    noise : float
        RMS of the start's ripple across the plane (m). See :class:`FoldNoise`.
    seed : int
        Seed of the start's ripple (-).
    push : float
        Real-world force density perpendicular to the rest plane on the upper part, along y (N/m^2).
        The paper's mechanism; 0 by default.
    folds : float
        Half-waves of the push: 0 uniform, n > 0 push sin(pi n a1 / L1) (1). n > 0 selects n half-waves
        (the earlier scene's load).
    taper : float
        The push at the hem, a fraction of the push at the rod, linear between (1).
    """

    name = "curtain"
    rank = 1
    summary = "a denim curtain drawn open along its rod, folding by itself (Figs 3-4)"
    size: tuple = (1.0, 1.2)
    nodes: tuple = (64, 64)
    gamma: float = 0.2
    xi: float = 1e-4
    fabric: str = "denim"

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

    def shipped_nodes(self) -> tuple:
        """The grid (M, N) this config ships on for its material (module docstring): the class's ``nodes``
        without a fabric; with one, (n, n) for the first n of :data:`FABRIC_GRIDS` on which the fold scale of the
        fabric's warp, (D H / (s mu g))^(1/4) (m; Cerda and Mahadevan 2003; s the ``scale``), spans at least
        :data:`~deformable.scenes.params.FOLD_SCALE_SPACINGS` of the smaller grid spacing
        (:func:`~deformable.scenes.params.resolving_nodes`), the finest of them when none does."""
        if not self.fabric:
            return tuple(type(self).nodes)
        fabric = self.named_fabric()
        l_f = fold_scale(float(fabric.bending[0]), self.scale * fabric.density * self.g, self.size[1])
        n = resolving_nodes(l_f, min(self.size), FABRIC_GRIDS) or FABRIC_GRIDS[-1]
        return (n, n)

    def replace(self, **changes) -> "CurtainConfig":
        """:meth:`SceneConfig.replace`; a config on the grid it ships on for its material (:meth:`shipped_nodes`)
        moves to the grid of the new material when ``changes`` give no ``nodes`` (``fabric=denim``: the grid that
        resolves denim; ``fabric=""``: the scene's own grid back). Explicit nodes win, and a grid set before is
        kept."""
        new = super().replace(**changes)
        if "nodes" not in changes and self.nodes == self.shipped_nodes() and new.nodes != new.shipped_nodes():
            new = dataclasses.replace(new, nodes=new.shipped_nodes())
        return new

    def build(self) -> Scene:
        """The Scene of this config."""
        L1, L2 = self.size
        start = FoldNoise(L1, self.noise, self.seed) if self.noise > 0 else VERTICAL
        sheet = Sheet(size=self.size, nodes=self.nodes, rest=VERTICAL, initial=start)
        forces = [Gravity(self.g)]
        if self.push:
            push, k = self.scale * self.push, math.pi * self.folds / L1

            def perpendicular(a1, a2, t):
                pattern = np.sin(k * a1) if self.folds else np.ones_like(a1)
                fy = push * pattern * (self.taper + (1.0 - self.taper) * a2 / L2)
                return np.stack([np.zeros_like(fy), fy, np.zeros_like(fy)], axis=-1)

            forces.append(BodyForce(perpendicular))
        if self.rings:
            constraints = self._rings()
        else:  # the top slides on the rail; its end at a1 = L1 is drawn
            constraints = [Slide("top", ("x", "y")), Pin("top-left")]
            if self.gather:
                travel, duration = self.gather * L1, self.draw_time

                def draw(t):
                    return (-travel * float(smooth_ramp(t / duration)), 0.0, 0.0)

                constraints.append(Pin("top-right", motion=draw))
        return Scene(sheet, self.material(), forces=forces, constraints=constraints, **self.scene_kwargs())

    def scene_kwargs(self) -> dict:
        """:meth:`SceneConfig.scene_kwargs`, with :data:`SELF_CONTACT` under the variational model when the config
        has no ``contact`` of its own (module docstring)."""
        kwargs = super().scene_kwargs()
        if kwargs["contact"] is None and self.force_model == "variational":
            kwargs["contact"] = SELF_CONTACT
        return kwargs

    def _rings(self) -> list:
        """The top carried by hooks on rings, the rings drawn together uniformly towards a1 = 0 (``rings = 1``).

        A hook at a1 keeps its height and is carried to x = a1 (1 - gather ramp(t / draw_time)); it swings freely
        along y (a ring on the rod). The top nodes between hooks slide in the rod's horizontal plane.
        """
        L1, (M, N) = self.size[0], self.nodes
        hooks = hook_nodes(self)
        constraints = [Slide("top", ("x", "y"))]  # the rod holds the height (FE: also the slope along the top)

        def carried(a1):
            def motion(t):
                return (-a1 * self.gather * float(smooth_ramp(t / self.draw_time)), 0.0, 0.0)
            return motion

        for m in hooks:
            a1 = m * L1 / (M - 1)
            constraints.append(Pin(np.array([[m, N - 1]]), motion=carried(a1) if self.gather and m else None,
                                   axes=("x", "z")))
        return constraints


@dataclass(frozen=True, kw_only=True)
class SilkyCurtainConfig(CurtainConfig):
    """Fig. 5, the silky curtain: the curtain in the lightest fabric measured (jacket-polyester, 113 g/m^2), on
    the 80 x 80 nodes that resolve its folds (module docstring).

    The paper makes its silky curtain by its scaling recipe (sections 3.1 and 4: mu, gamma, f scaled by 20, the
    micro parameters with them), which its semi-implicit scheme needs for a stable step; under the implicit step
    the real-world values run as they are. ``deformable params curtain-silky`` shows the step the semi-implicit
    scheme would need. Its folds are the narrowest of the three curtains: the fold scale (D H / (mu g))^(1/4) is
    6.8 cm, against denim's 7.8 and paper's 15 cm.
    """

    name = "curtain-silky"
    rank = 2
    summary = "the curtain in the lightest measured fabric, jacket-polyester 113 g/m^2 (Fig. 5)"
    nodes: tuple = (80, 80)
    fabric: str = "jacket-polyester"


@dataclass(frozen=True, kw_only=True)
class PaperConfig(SilkyCurtainConfig):
    """Fig. 6, paper: the curtain in ARCSim's estimate for paper (100 g/m^2, 1e6 N/m in stretching, 400 micro
    N m in bending), stiffer in both than every fabric preset, on 48 x 48 nodes (its fold scale 15 cm spans 7
    spacings). Its folds are wider than the silky curtain's by the bending-length theory's ((D / mu) ratio)^(1/4)
    = 22.2^(1/4) = 2.17; the paper study measures the ratio on both backends. The paper's own xi = 3e-6 N m
    (section 5, under its scaling by 20) would make its paper softer than the silky fabric here."""

    name = "paper"
    rank = 3
    summary = "the curtain in paper, stiffer in bending and stretching than every fabric (Fig. 6)"
    nodes: tuple = (48, 48)
    fabric: str = "paper"


def hook_nodes(cfg: CurtainConfig) -> np.ndarray:
    """The indices m of the top-row nodes that carry the curtain's hooks (``rings = 1``), both ends included.

    ``hooks = 0``: every top node; ``hooks = s > 0``: the nodes nearest to a1 = 0, s, 2 s, ... and the last.
    """
    M = cfg.nodes[0]
    if cfg.hooks == 0:
        return np.arange(M)
    step = max(1, int(round(cfg.hooks * (M - 1) / cfg.size[0])))
    return np.unique(np.append(np.arange(0, M, step), M - 1))
