r"""Claim 5 (section 5, Figs 3-8): the curtain, silky curtain, paper and flag, rendered with pyvista.

FD and FE side by side at equal times; the claim's check is that every figure
was drawn from runs that stayed bounded; what the pictures show is for the
reader to judge.
"""

from __future__ import annotations

import logging
import math

from validation.harness.backends import BACKENDS
from validation.harness.study import Figure, Table

from .analysis import classify
from .cases import RENDERS
from .claims import Claim, checks_of
from .pictures import render

log = logging.getLogger(__name__)


def measure(res, R, s) -> list[Claim]:
    """Claim 5 (section 5, Figs 3-8): the scenes rendered, FD and FE side by side."""
    rows = []
    made = []
    for sc, times, figs in RENDERS:
        fd, fe = R[("render", sc, "fd")], R[("render", sc, "fe")]
        frames = []
        for t in times:
            row = []
            for b, r, n in (("FD", fd, s["render_fd"]), ("FE", fe, s["render_fe"])):
                if t in r["renders"]:
                    grid = f"{n}x{n} nodes" if b == "FD" else f"{n - 1}x{n - 1} el."
                    row.append((f"{b} {grid}, t = {t:g} s", r["renders"][t]))
            if row:
                frames.append(row)
        for b, r in (("FD", fd), ("FE", fe)):
            rows.append((sc, figs, b, classify(r), r["t"], r["Gmax"], r.get("rail", math.nan)))
        if not frames:
            continue
        try:
            png = render(frames)
        except Exception as err:  # no OpenGL: the study's numbers still stand
            log.warning("render of %s failed: %s", sc, err)
            res.findings.append(f"Render of {sc} failed: {err}")
            continue
        name = f"render_{sc.replace('-', '_')}"
        made.append(name)
        res.figures.append(Figure(name, f"{figs}: `{sc}`, FD (left) and FE (right) at the same times; colour: "
                                        "displacement out of the rest plane, y (m)", image=png))
    res.tables.append(Table("renders", "Claim 5 (Figs 3-8): the rendered runs",
                            ("scene", "paper", "backend", "class", "t reached (s)", "max G_ii", "rail width / L1"), rows,
                            note="Pictures at the end of the report; both backends on the same scene and times."))
    res.check_all("claim 5: every figure rendered from a run that stayed bounded",
                  "each scene drawn, from runs that neither diverged nor ran away",
                  {f"{sc} ({b})": f"render_{sc.replace('-', '_')}" in made and classify(R[("render", sc, b)]) == "bounded"
                   for sc, _, _ in RENDERS for b in BACKENDS})
    return [Claim("Figs 3-8: curtain, silky curtain, paper, flag", "5",
                  f"{len(made)} of {len(RENDERS)} pictures, FD {s['render_fd']}x{s['render_fd']} and FE "
                  f"{s['render_fe'] - 1}x{s['render_fe'] - 1} el. (to be judged by eye)",
                  literal=len(made) == len(RENDERS), checks=checks_of(res, "claim 5"))]
