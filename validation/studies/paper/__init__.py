r"""Study ``paper``: the paper's own claims about control (sections 3-5), measured on both backends.

Ramos, Wu and Costa analyse the TPBF87 model, ``mu r_tt + gamma r_t + e(r) = f``
(eq. 11) with the force (14)-(15), ``e = sum_ij -d_i(alpha_ij d_j r) +
d_ij(beta_ij d_ij r)``, ``alpha_ij = eta_ij (G_ij - G0_ij)``, ``beta_ij = xi_ij
(B_ij - B0_ij)``, stepped by eq. (22)-(27) with the strength matrix K(r) of
eq. (20) lagged. Each claim below becomes runs of the scenes of
:mod:`deformable.scenes` (FD and FE), a section of the report that states the
claim, what was measured and whether it holds, and a row of the claims table.

The claims, one module each (their docstrings carry the derivations):

1. :mod:`.scaling`: macro-control, section 3.1, "(a mu, b gamma, c f) give the same visual effect";
2. :mod:`.damping`: section 3.1's damping regimes (over-damped, damped oscillation, undamped) on one sheet
   mode against the mass-spring formula, with each time scheme's numerical damping;
3. :mod:`.micro`: micro-control, section 3.2, eta_12 = xi_12 = 0, and alpha, beta given directly;
4. :mod:`.stability`: sections 3.2 and 5, "too large eta or xi loses equilibrium", the xi limit 1e-3;
5. :mod:`.sensitivity`: sections 4-5, "scaling mu, gamma, f makes xi effective" (Figs 5-6);
6. :mod:`.folds`: section 5, Figs 3-6, the folds of the drawn curtain counted over time and against xi, with
   the bending-length theory beside them, and paper against the silky curtain;
7. :mod:`.flag`: section 5, Figs 7-8, the phase of the flag's wave along it;
8. :mod:`.renders`: Figs 3-8 drawn with pyvista, FD and FE side by side (and ``python -m
   validation.studies.paper.media`` for the README's pictures and animations).

Claims 1-5 run the scenes as the paper does (:data:`.cases.PAPER`: its force, eta_12 = xi_12 = 0, its
curtain pushed across its plane); claims 6-8 measure the shipped scenes (:mod:`deformable.scenes`, the
energy-consistent model), with the paper's force beside them.

The claims table's verdicts are computed (:class:`.claims.Claim`): whether the
claim holds as the paper writes it is a measured boolean, and no verdict is
given unless every check of the claim passed.

Stability classes of a run: ``diverged`` (the DivergenceGuard of
:meth:`deformable.TimeStepper.run` stopped it: non-finite, or a displacement
above 100 sheet diagonals), ``runaway`` (finished, but some fibre was
stretched to more than twice its rest length, max G_ii > 4, a cloth the paper
wants area-invariant) and ``bounded``.
"""

from __future__ import annotations

import logging
import time

from validation.harness.backends import BACKENDS
from validation.harness.study import Levels, Study, Table

from . import damping, flag, folds, micro, renders, scaling, sensitivity, stability
from .analysis import classify, predictions, trajectory_difference
from .cases import (
    FROZEN,
    HANGING,
    MAP_SCENES,
    RUNAWAY_G,
    SCALE,
    SETTINGS,
    TIME_SCALE,
    TRIPLES,
    VISIBLE,
    XI_BASE,
    Case,
    fields,
    paper_config,
    run_case,
    scene_cases,
    spectrum,
)

__all__ = ["STUDY", "Case", "run_case", "SETTINGS", "spectrum", "predictions", "trajectory_difference", "classify",
           "RUNAWAY_G"]

log = logging.getLogger(__name__)


def _cases(s: dict) -> dict:
    """All cases of the study, by role."""
    grids = {"fd": s["fd"], "fe": s["fe"]}
    all_grids = {"fd": s["fd_grids"], "fe": s["fe_grids"]}
    c: dict = {}
    # claim 1: scaling, on the curtain
    base = paper_config("curtain")
    for b in BACKENDS:
        n, T = grids[b], s["t_short"]
        mk = lambda **kw: Case("run", "curtain", b, n, fields(**{"xi": XI_BASE, **kw}), t_end=T, every=10)  # noqa: E731
        c[("scale", b, "ref")] = mk()
        c[("scale", b, "P")] = mk(mu=SCALE * base.mu, gamma=SCALE * base.gamma, push=SCALE * base.push)
        c[("scale", b, "Q")] = mk(eta=base.eta / SCALE, xi=XI_BASE / SCALE)
        c[("scale", b, "time")] = Case("run", "curtain", b, n, fields(
            xi=XI_BASE, mu=TIME_SCALE**2 * base.mu, gamma=TIME_SCALE * base.gamma, g=base.g / TIME_SCALE**2),
            dt=TIME_SCALE * base.dt, t_end=TIME_SCALE * T, every=10)
        for a, bb, cc in TRIPLES:
            c[("scale", b, (a, bb, cc))] = mk(mu=a * base.mu, gamma=bb * base.gamma, push=cc * base.push,
                                              g=base.g * cc / a)
    # claim 2
    for b in BACKENDS:
        for name, variant in HANGING.items():
            c[("hanging", b, name)] = Case("hanging", "hanging", b, grids[b], fields(variant=variant),
                                           t_end=s["t_hang"])
        for v in ("alpha", "beta", "eta-xi"):
            c[("frozen", b, v)] = Case("frozen", "", b, grids[b], tag=v, t_end=FROZEN["t_end"], dt=FROZEN["dt"])
    # claim 3: (eta, xi) maps at the base grid; xi sweeps on every grid; (dt, h) maps
    for sc in MAP_SCENES:
        cfg = paper_config(sc)
        for b in BACKENDS:
            for eta in s["etas"]:
                for xi in s["xis"]:
                    c[("map", sc, b, eta, xi)] = Case("run", sc, b, grids[b], fields(eta=eta, xi=xi),
                                                      t_end=s["t_map"])
            for n in all_grids[b]:
                c[("spectrum", sc, b, n)] = Case("spectrum", sc, b, n)
                for xi in s["xis"]:
                    c[("xi-grid", sc, b, n, xi)] = Case("run", sc, b, n, fields(eta=cfg.eta, xi=xi),
                                                        t_end=s["t_map"])
                for dt in s["dts"]:
                    c[("dt", sc, b, n, dt)] = Case("run", sc, b, n, fields(eta=cfg.eta, xi=0.0), dt=dt,
                                                   t_end=s["t_map"])
    # claim 4: sensitivity to xi
    for sc in ("curtain", "curtain-silky"):
        dt = paper_config(sc).dt
        for b in BACKENDS:
            for xi in s["sens_xis"]:
                c[("sens", sc, b, xi)] = Case("run", sc, b, grids[b], fields(xi=xi), t_end=s["t_sens"],
                                              every=max(1, int(round(0.02 / dt))))
    # section 5 on the shipped scenes (folds, flag, pictures) and section 3.1's damping regimes
    c.update(scene_cases(s))
    return c


def _runs(runner, cases: dict) -> dict:
    unique = sorted(set(cases.values()), key=lambda k: -k.cost)  # long first: less idle time at the end
    done = dict(zip(unique, runner.map(run_case, unique, desc="paper")))
    return {key: done[case] for key, case in cases.items()}


def fill(res, levels: int, runner) -> None:
    """The paper study; ``levels`` 1 is the quick set (claims 1-5: FD 12 x 12 nodes, FE 6 x 6 elements; section 5:
    the flag on FD 32 x 32, FE 16 x 16 elements, the curtain and its xi sweep on FD 64 x 64, FE 32 x 32
    elements, curtain-silky and paper on FD 80 x 80, FE 40 x 40 elements), 2 the full one."""
    s = SETTINGS[levels]
    cases = _cases(s)
    t0 = time.perf_counter()
    R = _runs(runner, cases)
    log.info("paper: %d runs in %.1f s", len(set(cases.values())), time.perf_counter() - t0)
    res.config.update({"settings": {k: list(v) if isinstance(v, tuple) else v for k, v in s.items()},
                       "runaway_G": RUNAWAY_G, "visible": VISIBLE, "scale": SCALE, "xi_base": XI_BASE,
                       "time_scale": TIME_SCALE, "frozen": FROZEN,
                       "grids": "FD: nodes a side; FE: nodes a side = elements + 1"})
    modes = {k[1:]: v for k, v in R.items() if k[0] == "damping"}
    claims = (scaling.measure(res, R, s) + damping.measure(res, modes, s) + micro.measure(res, R, s)
              + stability.measure(res, R, s) + sensitivity.measure(res, R, s) + folds.measure(res, R, s)
              + flag.measure(res, R, s) + renders.measure(res, R, s))
    res.tables.insert(0, Table("claims", "Claims of the paper and what was measured",
                               ("claim", "section", "measured", "verdict"), [c.row() for c in claims],
                               note="One row per claim; the sections below give the runs. A verdict is computed: "
                                    "'holds' when the claim as written holds on the measurements for every case "
                                    "it states; 'false' when it fails for any of them, with the narrower condition "
                                    "under which the measurements show it true ('holds only ...'); 'holds where "
                                    "measured ...; not judged ...' when a case it states has no measurement (a run "
                                    "that diverged before its analysis window), with what happened to it; 'not "
                                    "judged' for pictures; no verdict when a check of the claim failed. Grids: FD "
                                    f"{s['fd']} x {s['fd']} nodes, FE {s['fe'] - 1} x {s['fe'] - 1} elements."))
    res.data["claims"] = [dict(statement=c.statement, literal=c.literal, checks=list(c.checks), verdict=c.verdict,
                               not_judged=c.not_judged) for c in claims]


STUDY = Study("paper", "the paper's claims (sections 3-5) reproduced and explained: scaling, micro-control, "
              "stability, xi, figures", Levels(quick=1, full=2, minimum=1, maximum=2), fill, in_default=False)
