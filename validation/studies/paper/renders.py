r"""Section 5 (Figs 3-8) drawn: the shipped scenes, FD and FE side by side.

Each picture shows one scene of :mod:`deformable.scenes` (its own model and
parameters, run for section 5's measurements, :mod:`.folds` and :mod:`.flag`)
at a start, middle and end frame, FD above and FE below, coloured by the
displacement out of the rest plane (y), with the curtain's rod or the flag's
pole drawn in. The check is that every picture was drawn from runs that
stayed bounded; what the pictures show is for the reader to judge, and the
numbers of the other sections say how far to trust them. The curtain under
the paper's force (14) is drawn too, beside its measured folds.

:func:`scene_picture` makes the PNG of a scene from its runs; the README's
animations and stills are made by ``python -m validation.studies.paper.media``
(:mod:`.media`, into docs/scenes/).
"""

from __future__ import annotations

import logging

import numpy as np

from deformable import scenes
from validation.harness.backends import BACKENDS
from validation.harness.study import Figure, Table

from .analysis import classify
from .cases import RENDERS, grid_label, scene_grids
from .claims import Claim, checks_of
from .pictures import render

__all__ = ["PICTURES", "picture_runs", "decorations", "scene_picture", "measure"]

log = logging.getLogger(__name__)

#: the pictures: (name, scene, force model, caption head)
PICTURES = tuple((sc.replace("-", "_"), sc, "variational", f"{figs}: `{sc}`") for sc, figs in RENDERS) + (
    ("curtain_tpbf87", "curtain", "tpbf87", "Figs 3-4 under the paper's force (14): `curtain --force-model tpbf87`"),)


def picture_runs(R: dict, scene: str, force_model: str = "variational") -> dict:
    """The runs of a scene that carry its frames, by backend (the flag's; the others' at the scene's own xi)."""
    if scene == "flag":
        return {b: R[("flag", b, force_model)] for b in BACKENDS}
    return {b: R[("folds", scene, b, force_model, scenes.config(scene, force_model=force_model).xi)] for b in BACKENDS}


def decorations(scene: str) -> list:
    """The rod a curtain hangs from, or the flag's pole, as segments ((x, y, z), (x, y, z)) in the scene's
    coordinates (m); none for ``hanging``."""
    L1, L2 = scenes.config(scene).size
    if scene == "flag":
        return [((0.0, 0.0, -0.15 * L2), (0.0, 0.0, 1.08 * L2))]
    if scene == "hanging":
        return []
    return [((-0.04 * L1, 0.0, L2), (1.04 * L1, 0.0, L2))]


def scene_picture(R: dict, scene: str, nodes: dict, force_model: str = "variational") -> bytes:
    """PNG: FD (top row) and FE (bottom row) at the run's picture times; ``nodes`` by backend."""
    runs = picture_runs(R, scene, force_model)
    frames = []
    for b in BACKENDS:
        r = runs[b]
        frames.append([(grid_label(b, nodes[b]), t, pts) for t, pts in sorted(r["renders"].items())])
    return render([row for row in frames if row], size=(300, 280), lines=decorations(scene))


def measure(res, R, s) -> list[Claim]:
    """Section 5 (Figs 3-8): the shipped scenes drawn, FD and FE side by side."""
    rows, made = [], []
    for name, sc, fm, head in PICTURES:
        nodes = dict(zip(BACKENDS, scene_grids(s, sc)))
        runs = picture_runs(R, sc, fm)
        for b in BACKENDS:
            r = runs[b]
            rows.append((sc, fm, b.upper(), grid_label(b, nodes[b]), classify(r), r["t"], r["Gmax"]))
        try:
            png = scene_picture(R, sc, nodes, fm)
        except Exception as err:  # no OpenGL: the study's numbers still stand
            log.warning("render of %s failed: %s", sc, err)
            res.findings.append(f"Render of {sc} ({fm}) failed: {err}")
            continue
        made.append(name)
        stopped = "".join(f"; {b.upper()} diverged at t = {runs[b]['t']:.3g} s (its frames before that only)"
                          for b in BACKENDS if runs[b]["status"] == "diverged")
        res.figures.append(Figure(f"scene_{name}", f"{head}, FD (top) and FE (bottom) at the start, middle and end; "
                                                   f"colour: displacement out of the rest plane, y (m){stopped}",
                                  image=png))
    res.tables.append(Table("renders", "Section 5 (Figs 3-8): the rendered runs",
                            ("scene", "force model", "backend", "grid", "class", "t reached (s)", "max G_ii"), rows,
                            note="Pictures at the end of the report; both backends on the same scene and times. The "
                                 "shipped scenes (deformable.scenes, energy-consistent model); the last pair is the "
                                 "curtain under the paper's force (14)."))
    res.check_all("section 5, pictures: every scene drawn from runs that stayed bounded",
                  "each shipped scene drawn, FD and FE, from runs that neither diverged nor ran away",
                  {f"{sc} ({b.upper()})": sc.replace("-", "_") in made and classify(picture_runs(R, sc)[b]) == "bounded"
                   for sc, _ in RENDERS for b in BACKENDS})
    _compatibility(res, R, s)
    return [Claim("Figs 3-8: curtain, silky curtain, paper, flag", "5",
                  f"{len(made)} of {len(PICTURES)} pictures of the shipped scenes, FD and FE (to be judged by eye)",
                  literal=None, checks=checks_of(res, "section 5, pictures") + (len(made) == len(PICTURES),))]


def _compatibility(res, R, s) -> None:
    """Section 3.2's compatibility test tracked over the section 5 runs: at every sample (each
    ``SAMPLE_EVERY`` s) the paper's ratio and cosine of eq. (10) on the state's own G and B (worst over the
    resolved points of both comparisons). Reported, not checked: the deformed sheet is a surface, so what
    the numbers measure is how coherent the discrete tensors are (FD's node tensors of eq. (18)-(19) are
    first order, docs/design.md)."""
    from .pictures import panels_figure

    lines_r, lines_c, rows = [], [], []
    colour = {"fd": "tab:blue", "fe": "tab:orange"}
    for _, sc, fm, _ in PICTURES:
        if fm != "variational":
            continue
        for b, r in picture_runs(R, sc, fm).items():
            track = [m for m in r.get("compatibility", ()) if m[0] > 0]
            if not track:
                continue
            t, ratio, cosine, resolved = (np.array(v, float) for v in zip(*track))
            style = {"curtain": "-", "curtain-silky": "--", "paper": "-.", "flag": ":"}[sc]
            label = f"{sc} {b.upper()}"
            lines_r.append(dict(x=t, y=np.maximum(np.abs(np.log(ratio)), 1e-16), label=label, style=style,
                                color=colour[b]))
            lines_c.append(dict(x=t, y=np.maximum(1 - cosine, 1e-16), label=label, style=style, color=colour[b]))
            last = int(np.flatnonzero(np.isfinite(ratio))[-1]) if np.isfinite(ratio).any() else -1
            rows.append((sc, b.upper(), float(t[last]), float(ratio[last]), float(cosine[last]),
                         float(resolved[last]), float(np.nanmax(np.abs(np.log(ratio)))), float(np.nanmax(1 - cosine))))
    res.tables.append(Table("compatibility_track", "Section 3.2's compatibility test over the section 5 runs (the "
                            "energy-consistent model, each scene's own xi)",
                            ("scene", "backend", "t (s)", "worst ratio", "smallest cosine", "fraction resolved",
                             "largest |log ratio| over the run", "largest 1 - cosine over the run"), rows,
                            note="At every sample the test of eq. (10) (deformable.geometry.check_compatibility) on "
                                 "the state's own G and B at the nodes, the worst ratio |u| / |v| and the smallest "
                                 "cosine over both comparisons' resolved points; the row gives the last sample. The "
                                 "deformed sheet is a surface: these measure how coherent the discrete tensors "
                                 "are, not the model. The series of deformable run carry the same test pointwise "
                                 "(compatibility_ratio, compatibility_cosine)."))
    if rows:
        resolved = [r[5] for r in rows]
        res.findings.append(
            f"Section 3.2's test on the section 5 runs' own tensors: at their last sample it resolves "
            f"{min(resolved):.2%} to {max(resolved):.2%} of the points (the rest guarded: a nearly developable "
            f"folded sheet's compared vectors vanish), and there the worst ratio lies between "
            f"{min(r[3] for r in rows):.3g} and {max(r[3] for r in rows):.3g}, the smallest cosine between "
            f"{min(r[4] for r in rows):.3g} and {max(r[4] for r in rows):.3g}: on a folded sheet the third "
            "derivatives the test compares are at the grid's resolution, so the test says little about a "
            "deformed state; on smooth rest surfaces it passes (the compatibility study, and "
            "tests/deformable/io/test_series.py on a sphere's cap).")
    if lines_r:
        res.figures.append(Figure("compatibility_track", "Section 3.2's compatibility test over the section 5 runs: "
                                  "|log ratio| (left) and 1 - cosine (right), worst over the resolved points",
                                  image=panels_figure([
                                      dict(title="ratio |u| / |v|", xlabel="t (s)", ylabel="|log ratio| (1)",
                                           lines=lines_r, ylog=True),
                                      dict(title="cosine of (u, v)", xlabel="t (s)", ylabel="1 - cosine (1)",
                                           lines=lines_c, ylog=True)], "The compatibility test over time",
                                      width=5.6, height=4.0)))
