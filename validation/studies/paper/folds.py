r"""The folds of a drawn curtain (section 5, Figs 3-6), measured: their number and width, and the theory beside them.

The fold measure. The curtain hangs in the x-z plane; a fold is a ridge or a
valley of its displacement out of that plane, y. Along a row of constant
height a2 (at :data:`ROWS`, 30 % to 90 % of the height from the hem), y is
sampled as a function of the *material* coordinate a1 (:data:`SAMPLES` points
per grid spacing; FD shows its node polyline, FE its cubic surface). A
gathered row folds like an accordion, its folds overlap in x, and they ride
on a slow bulge or tilt of the whole row, so neither y against x nor the sign
of ``y - mean(y)`` counts them well. Counted instead are the row's
alternating extrema with hysteresis (the "peak detection" of Billauer's
``peakdet``, a Schmitt trigger on the signal's own extrema): scanning along
a1, a maximum is registered once y has fallen from it by at least delta, a
minimum once y has risen by delta, alternately, so a wiggle smaller than
delta is never a fold, and a trend never makes one. An extremum at either
end of the row is not a fold. ``delta = max(DELTA_FRACTION * ptp(y),
DELTA_MIN)``: a tenth of the row's peak-to-peak, and never below 6 mm, above
the largest peak-to-peak of the scenes' seeded ripple (``noise`` = 1 mm RMS:
at most 5.8 mm over the seeds 1 to 50), so that the ripple is not counted
before folds grow.

- fold count n of a row: its number of extrema (ridges plus valleys; a sine
  with k half-waves over the row has k);
- fold width of a row: the mean distance in a1 between consecutive extrema
  (material length, m), and in grid spacings h1; the narrowest fold is the
  smallest such distance;
- fold wavelength lambda = 2 x the fold width (ridge to ridge);
- a snapshot's count and width: medians over the rows (each sampled every
  :data:`SAMPLE_EVERY` s); a run's: medians over the snapshots of its last
  :data:`LATE` s, when the rod is drawn and the folds have settled.

The theory beside it (:func:`deformable.scenes.fold_wavelength`): a sheet
held straight by the tension of its own weight and compressed across wrinkles
at ``lambda ~ (D H / (mu g))^(1/4)`` (Cerda & Mahadevan 2003, Phys. Rev. Lett.
90, 074302), D = 2 xi under the energy-consistent model, H the height. So the
count over a fixed width scales as ``xi^(-1/4)``, and the ratio of the fold
wavelengths of two sheets is ``(xi_a mu_b / (xi_b mu_a))^(1/4)``: 2.17 for
``paper`` (ARCSim's estimate, D = 400 micro N m, 100 g/m^2) against
``curtain-silky`` (jacket-polyester's warp, D = 20.3 micro N m, 113 g/m^2). The
prefactor ``C = lambda / fold_wavelength`` is fitted, not predicted (the
theory gives only the scaling); over a xi sweep it should stay constant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from deformable import scenes
from validation.harness.backends import BACKENDS
from validation.harness.study import Figure, Table

from .analysis import classify
from .cases import ROWS, SAMPLE_EVERY, SAMPLES, grid_label, scene_grids
from .claims import Claim, checks_of
from .pictures import panels_figure

__all__ = ["ROWS", "SAMPLES", "DELTA_FRACTION", "DELTA_MIN", "SAMPLE_EVERY", "LATE", "extrema", "RowFolds",
           "row_folds", "snapshot_folds", "fold_series", "late_folds", "power_fit", "exponent_fit",
           "wavelength_exponent", "count_exponent", "narrowest_check", "EXPONENT_WINDOW", "WAVELENGTH_WINDOW",
           "NARROWEST", "COUNT_SPAN", "FoldRuns"]

#: hysteresis: a fold must rise (fall) by this fraction of the row's peak-to-peak ...
DELTA_FRACTION = 0.1
#: ... and by at least this much (m): above the peak-to-peak of the scenes' seeded ripple (1 mm RMS)
DELTA_MIN = 6e-3
#: a run's count and width are the medians over its last LATE seconds
LATE = 0.4


def extrema(y, delta: float) -> np.ndarray:
    """Indices of the alternating extrema of ``y`` with hysteresis ``delta`` (module docstring).

    An extremum is registered once the signal has moved back from it by at least ``delta``; maxima and
    minima alternate; an extremum at either end of ``y`` is dropped. ``delta`` must be positive.
    """
    y = np.asarray(y, float)
    if not delta > 0:
        raise ValueError(f"hysteresis delta must be positive, got {delta!r}")
    found = []
    hi = lo = 0
    looking = 0  # +1: for a maximum, -1: for a minimum, 0: either (before the first extremum)
    for i in range(1, y.size):
        if y[i] > y[hi]:
            hi = i
        if y[i] < y[lo]:
            lo = i
        if looking >= 0 and y[hi] - y[i] >= delta:
            found.append(hi)
            looking, lo = -1, i
        elif looking <= 0 and y[i] - y[lo] >= delta:
            found.append(lo)
            looking, hi = 1, i
    return np.array([k for k in found if 0 < k < y.size - 1], dtype=int)


@dataclass(frozen=True)
class RowFolds:
    """The folds of one row: count, mean and narrowest width (m), where the narrowest is (a1 of its middle, m;
    NaN with fewer than two folds), peak-to-peak of y (m)."""

    count: int
    width: float
    narrowest: float
    ptp: float
    narrowest_at: float = math.nan


def row_folds(a, y) -> RowFolds:
    """The folds of a row: y (m) sampled at the material coordinates a (m), increasing."""
    a, y = np.asarray(a, float), np.asarray(y, float)
    ptp = float(np.ptp(y))
    idx = extrema(y, max(DELTA_FRACTION * ptp, DELTA_MIN))
    gaps = np.diff(a[idx])
    if not gaps.size:
        return RowFolds(count=int(idx.size), width=math.nan, narrowest=math.nan, ptp=ptp)
    k = int(np.argmin(gaps))
    return RowFolds(count=int(idx.size), width=float(gaps.mean()), narrowest=float(gaps[k]), ptp=ptp,
                    narrowest_at=float(0.5 * (a[idx[k]] + a[idx[k + 1]])))


def snapshot_folds(a, rows) -> dict:
    """The folds of a snapshot: ``rows`` (R, P) of y at the material coordinates a (P,).

    Returns count (median over rows), width (median of the rows' mean widths, m; NaN when no row has two
    folds), narrowest (m, over all rows) and narrowest_at (its a1, m), ptp (largest peak-to-peak, m).
    """
    per = [row_folds(a, y) for y in np.asarray(rows)]
    widths = [r.width for r in per if np.isfinite(r.width)]
    narrow = min((r for r in per if np.isfinite(r.narrowest)), key=lambda r: r.narrowest, default=None)
    return dict(count=float(np.median([r.count for r in per])), width=float(np.median(widths)) if widths else math.nan,
                narrowest=narrow.narrowest if narrow else math.nan,
                narrowest_at=narrow.narrowest_at if narrow else math.nan, ptp=max(r.ptp for r in per),
                counts=[r.count for r in per])


def fold_series(a, t, rows) -> list[dict]:
    """:func:`snapshot_folds` of each snapshot: rows (T, R, P), times t (T,); each dict gains ``t``."""
    return [dict(snapshot_folds(a, r), t=float(tk)) for tk, r in zip(t, rows)]


def late_folds(series: list[dict], t_end: float, late: float = LATE) -> dict:
    """A run's folds: medians of count and width over the snapshots with t >= t_end - late; the narrowest."""
    tail = [s for s in series if s["t"] >= t_end - late - 1e-9]
    if not tail:
        return dict(count=math.nan, width=math.nan, narrowest=math.nan, snapshots=0)
    widths = [s["width"] for s in tail if np.isfinite(s["width"])]
    narrow = [s["narrowest"] for s in tail if np.isfinite(s["narrowest"])]
    return dict(count=float(np.median([s["count"] for s in tail])),
                width=float(np.median(widths)) if widths else math.nan,
                narrowest=min(narrow) if narrow else math.nan, snapshots=len(tail))


def power_fit(x, y) -> tuple[float, float]:
    """Least-squares exponent p and prefactor c of ``y = c x^p`` (log-log); NaN with fewer than two points."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = (x > 0) & (y > 0) & np.isfinite(y)
    if ok.sum() < 2:
        return math.nan, math.nan
    p, logc = np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)
    return float(p), float(math.exp(logc))


def exponent_fit(x, y) -> tuple[float, float, int]:
    """Least-squares exponent p of ``y = c x^p`` (log-log), its standard error (NaN with fewer than three points:
    no degree of freedom left) and the number of points used (x > 0, y > 0 and finite)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = (x > 0) & (y > 0) & np.isfinite(y)
    n = int(ok.sum())
    if n < 2:
        return math.nan, math.nan, n
    X, Y = np.log(x[ok]), np.log(y[ok])
    p, c = np.polyfit(X, Y, 1)
    if n < 3:
        return float(p), math.nan, n
    resid = Y - (p * X + c)
    se = math.sqrt(float(resid @ resid) / (n - 2) / float(np.sum((X - X.mean()) ** 2)))
    return float(p), se, n


# -- the report section --------------------------------------------------------
#: the window of the fitted exponent of the fold count against xi, around the theory's -1/4 (module docstring of
#: measure())
EXPONENT_WINDOW = (-0.4, -0.12)
#: the window of the fitted exponent of the fold wavelength against xi, around the theory's 1/4: the same law
WAVELENGTH_WINDOW = (-EXPONENT_WINDOW[1], -EXPONENT_WINDOW[0])
#: a fold count is fitted against xi only when the counts take at least COUNT_SPAN[0] distinct values and the
#: largest is at least COUNT_SPAN[1] times the smallest (measure()'s docstring)
COUNT_SPAN = (3, 2.0)


def wavelength_exponent(xis, wavelengths, window=WAVELENGTH_WINDOW) -> tuple[bool, str, float, float]:
    r"""The check of ``lambda ~ xi^p`` against the bending-length theory's 1/4 (Cerda & Mahadevan 2003).

    ``xis`` (N m) and the runs' fold wavelengths (m). Passes when at least three runs have a wavelength, p lies in
    ``window`` and its standard error is at most half the window's width (the fit resolves the window).
    Returns (passed, observed text, p, standard error).
    """
    p, se, n = exponent_fit(xis, wavelengths)
    lo, hi = window
    pts = ", ".join(f"{w:.3g} m" if np.isfinite(w) else "-" for w in wavelengths)
    if n < 3:
        return False, (f"not measurable: {n} run(s) with a fold wavelength (lambda {pts}), at least 3 needed for an "
                       "exponent and its uncertainty"), p, se
    ok = lo <= p <= hi and se <= (hi - lo) / 2
    return ok, (f"lambda ~ xi^{p:.3f} +- {se:.3f} (standard error, {n} points, {n - 2} degree(s) of freedom; "
                f"lambda {pts})" + ("" if se <= (hi - lo) / 2 else
                                    f"; the standard error exceeds half the window ({(hi - lo) / 2:.2f})")), p, se


def count_exponent(xis, counts, window=EXPONENT_WINDOW, span=COUNT_SPAN) -> tuple[bool, str, float]:
    """The check of ``count ~ xi^p`` against the theory's -1/4, or its refusal.

    A fold count is an integer: fitted to counts that take few values (fewer than ``span[0]`` distinct ones, or
    the largest below ``span[1]`` times the smallest) its exponent is set by where one fold is gained or lost,
    not by the law, and the check does not pass ("not measurable"). Returns (passed, observed text, p).
    """
    c = [float(v) for v in counts]
    text = ", ".join(format(v, "g") for v in c)
    pos = [v for v in c if np.isfinite(v) and v > 0]
    distinct = len(set(pos))
    if len(pos) < len(c) or distinct < span[0] or max(pos) < span[1] * min(pos):
        spread = (max(pos) - min(pos)) if pos else math.nan
        return False, (f"not measurable: counts {text} ({distinct} distinct value(s), differ by at most "
                       f"{spread:g} fold(s); a fit needs at least {span[0]} distinct counts and the largest at least "
                       f"{span[1]:g} times the smallest)"), math.nan
    p, _ = power_fit(xis, c)
    return bool(window[0] <= p <= window[1]), f"p = {p:.3f} (counts {text})", p


def at_least(width_h: float, least: float) -> bool:
    """A fold ``width_h`` grid spacings wide is at least ``least`` wide, to round-off (a width is a difference of
    sample positions over h: three spacings come out as 2.9999999999999964); NaN (no fold pair) is not."""
    return bool(np.isfinite(width_h) and width_h >= least * (1 - ROUND_OFF))


def narrowest_check(narrowest_h: dict, least: float) -> tuple[bool, str]:
    """Every run's narrowest fold (``{label: grid spacings}``) at least ``least`` spacings (:func:`at_least`);
    fails over no run or a run without a fold pair (NaN). Returns (passed, observed text naming every run's
    narrowest)."""
    if not narrowest_h:
        return False, "no run to check"
    bad = [k for k, v in narrowest_h.items() if not at_least(v, least)]
    each = ", ".join(f"{k} {v:.2g} h" for k, v in narrowest_h.items())
    return not bad, (f"{len(narrowest_h) - len(bad)} of {len(narrowest_h)} hold ({each})"
                     + (f"; not: {', '.join(bad)}" if bad else ""))
#: the narrowest fold a grid may show, in grid spacings
NARROWEST = 3.0
#: the relative round-off a fold width in grid spacings carries (:func:`at_least`)
ROUND_OFF = 1e-9
#: FD and FE fold wavelengths agree when they differ by at most COUNT_TOLERANCE x the larger
COUNT_TOLERANCE = 0.2
#: Figs 5-6 with "little stretching" (issue 29): at STRETCH_TIME (s), the median and largest fibre stretch
STRETCH_TIME, STRETCH_MEDIAN, STRETCH_LARGEST = 1.0, 0.02, 0.05


def theory_ratio() -> float:
    """The fold wavelength of ``paper`` over ``curtain-silky`` by the bending-length theory (module docstring):
    ((xi / mu) of paper over the silky curtain's)^(1/4), their warps' (1)."""
    cp, cs = scenes.config("paper"), scenes.config("curtain-silky")
    return float(((cp.xi / cp.mu) / (cs.xi / cs.mu)) ** 0.25)


def run_folds(r: dict) -> dict:
    """The fold measure of a recorded run (:func:`validation.studies.paper.cases.scene_cases`): its series and
    late values, widths also in grid spacings h, the fold wavelength lambda = 2 x width and the theory's;
    ``below``: how many snapshots have a fold narrower than :data:`NARROWEST` h, ``below_at``: the range of a1
    (m) where those narrowest folds sit."""
    from deformable.scenes import fold_wavelength

    series = fold_series(r["a"], r["rows_t"], r["rows"])
    late = late_folds(series, r["t"])
    cfg = r["config"]
    theory = fold_wavelength(cfg["xi"], cfg["mu"], cfg["g"], cfg["size"][1], cfg["scale"], cfg["force_model"])
    narrow_all = [s["narrowest"] for s in series if np.isfinite(s["narrowest"])]
    below = [s for s in series if np.isfinite(s["narrowest"]) and not at_least(s["narrowest"] / r["h"], NARROWEST)]
    return dict(series=series, count=late["count"], width=late["width"], width_h=late["width"] / r["h"],
                narrowest_h=late["narrowest"] / r["h"], ever_narrowest_h=min(narrow_all) / r["h"] if narrow_all
                else math.nan, below=len(below),
                below_at=(min(s["narrowest_at"] for s in below), max(s["narrowest_at"] for s in below)) if below
                else (math.nan, math.nan), wavelength=2.0 * late["width"], theory=theory,
                prefactor=2.0 * late["width"] / theory if theory > 0 else math.nan,  # xi = 0: no bending length
                depth=max((s["ptp"] for s in series if s["t"] >= r["t"] - LATE - 1e-9), default=math.nan))


def measure(res, R: dict, s: dict) -> list:
    r"""Section 5 (Figs 3-6): fold count and width of the drawn curtain over time and against xi, both backends
    and both force models; paper against curtain-silky.

    Checks (energy-consistent model, the shipped scenes):

    - the runs finish bounded (the measurements stand on them);
    - the fold wavelength against xi (:func:`wavelength_exponent`): the least-squares exponent of ``lambda = c
      xi^p`` within :data:`WAVELENGTH_WINDOW` around the theory's 1/4 (the bending length ``(D H / (mu
      g))^(1/4)``, D = 2 xi: Cerda & Mahadevan 2003), with its standard error at most half the window. The
      wavelength (twice the mean distance between a row's extrema, medians over rows and late snapshots) is a
      continuous measure: the primary one. The window: the sweeps span one decade of xi (1e-4 to 1e-3, the
      decade the grids resolve: three values quick, five full), and an error of 15 % of lambda at either end
      moves the slope by up to ``log(1.15 / 0.85) / log(10) = 0.13``; the window is 1/4 +- 0.14;
    - the fold count against xi (:func:`count_exponent`): ``count = c xi^p`` with p in :data:`EXPONENT_WINDOW`
      around -1/4, fitted only where the counts can carry an exponent: at least :data:`COUNT_SPAN` [0] distinct
      counts, the largest at least :data:`COUNT_SPAN` [1] times the smallest. Over the decade the theory
      predicts a count falling by ``10^(1/4) = 1.8``: counts such as 2, 2, 1 differ by one fold, and a slope
      through them says where a fold was lost, not the law (one fold at either end moves it by ``log(2) /
      log(10) = 0.3``, twice the window); then the check does not pass, "not measurable";
    - the curtain's sweep: never a fold narrower than :data:`NARROWEST` grid spacings (the narrowest pair of
      consecutive extrema over every row of every snapshot, each energy-consistent run of the sweep named), and
      FD and FE fold wavelengths agree within :data:`COUNT_TOLERANCE` of the larger (the wavelength: counts of 1
      to 3 agree within one fold whatever the grids do). The sweep runs on its own
      grids (``folds``: FD 64, FE 32 el. at the quick level) over a decade of xi with the curtain's density and
      stretching, and the shipped curtain (denim) at its own;
    - paper against curtain-silky: the ratio of fold wavelengths within ``r^p`` for p in the window, r =
      (xi / mu) of paper over that of curtain-silky (22.2: 1.45 to 3.46 around the theory's 2.17), the same
      tolerance on the same law.
    - Figs 5-6 as the paper describes them (light and stiff sheets): curtain-silky and paper with little
      stretching, the median fibre stretch at most
      :data:`STRETCH_MEDIAN` and the largest at most :data:`STRETCH_LARGEST` at :data:`STRETCH_TIME`, and
      their *narrowest* fold over every row of the snapshots of the last :data:`LATE` s at least
      :data:`NARROWEST` grid spacings (a median width would pass a curtain whose folds stack one spacing apart
      where the rod gathers them).

    The paper's force (tpbf87) is measured and reported, not checked: at xi = 0 (section 5's value) it has no
    bending stiffness at all, and at xi > 0 none about the flat sheet and a negative one where xi B < 0
    (docs/design.md, "Three readings"; claim 3), so nothing in it sets a fold width. Its runs judge the claim
    where they finish; the runs that diverge are named as not judged, with when they stopped.
    """
    runs = FoldRuns(R, s)
    _tables(res, runs)
    fits = _sweep_checks(res, runs)
    _narrowest_checks(res, runs)
    _agreement_check(res, runs)
    _sheet_checks(res, runs)
    ratio, expected = _ratio_check(res, runs)
    _findings(res, runs, fits, ratio, expected)
    _figures(res, runs, fits)
    checks = checks_of(res, "section 5, curtain folds") + checks_of(res, "section 5, paper against")
    c = curtain_claim(fits, ratio, {(k[2], k[4]): dict(status=r["status"], t=r["t"], steps=r["steps"], Gmax=r["Gmax"],
                                                        count=f["count"], narrowest_h=f["ever_narrowest_h"],
                                                        width_h=f["width_h"])
                                    for k, (r, f) in runs.paper_force.items()})
    return [Claim("Figs 3-6: the curtain drawn open folds; scaled parameters and xi = 3e-6 change its folds", "5",
                  c["measured"], literal=c["literal"], checks=checks, holds_when=c["holds_when"],
                  not_judged=c["not_judged"])]


class FoldRuns:
    """Section 5's fold runs, ``R``'s ("folds", scene, backend, force model, xi) in the study's order, with their
    fold measures (:func:`run_folds`) and the groups the report takes them in.

    ``keys``: the runs; ``F``: {key: fold measure}; ``var``: the energy-consistent runs' measures; ``swept``: the
    curtain's xi sweep among them; ``sweep``: {backend: [(xi, measure)]} of the sweep, by xi; ``sheets``: the runs
    of curtain-silky and paper at their own xi (Figs 5-6); ``paper_force``: {key: (run, measure)} under the
    paper's force (14).
    """

    def __init__(self, R: dict, s: dict):
        self.R, self.s = R, s
        self.keys = [k for k in R if k[0] == "folds"]
        self.F = {k: run_folds(R[k]) for k in self.keys}
        self.var = {k: self.F[k] for k in self.keys if k[3] == "variational"}
        self.swept = {k: f for k, f in self.var.items() if k[1] == "curtain"}
        self.sweep = {b: [(k[4], self.F[k]) for k in sorted(self.var) if k[1] == "curtain" and k[2] == b]
                      for b in BACKENDS}
        self.sheets = {k: R[k] for k in self.var if k[1] in ("curtain-silky", "paper")
                       and k[4] == scenes.config(k[1]).xi}
        self.paper_force = {k: (R[k], self.F[k]) for k in self.keys if k[3] == "tpbf87"}

    def grid(self, b: str, scene: str = "curtain") -> str:
        """The grid of a scene's runs on backend ``b``, as the report names it."""
        return grid_label(b, dict(zip(BACKENDS, scene_grids(self.s, scene)))[b])


def _tables(res, runs: FoldRuns) -> None:
    """The folds of every run, late and over time."""
    R, F, s = runs.R, runs.F, runs.s
    rows = []
    for k in runs.keys:
        _, sc, b, fm, xi = k
        r, f = R[k], F[k]
        n = dict(zip(BACKENDS, scene_grids(s, sc)))[b]
        rows.append((sc, b.upper(), n if b == "fd" else f"{n - 1} el.",
                     fm, xi, classify(r), r["t"], f["count"],
                     f["width"], f["width_h"], f["narrowest_h"], f["ever_narrowest_h"], f["below"], *f["below_at"],
                     f["wavelength"], f["theory"],
                     f["prefactor"], f["depth"]))
    res.tables.append(Table(
        "folds", "Section 5 (Figs 3-6): folds of the drawn curtain against xi, both backends and force models",
        ("scene", "backend", "grid", "force model", "xi (N m)", "class", "t reached (s)", "folds", "fold width (m)",
         "fold width (h)", "narrowest, late (h)", "narrowest, ever (h)", f"snapshots < {NARROWEST:g} h",
         "there from a1 (m)", "to a1 (m)", "lambda (m)", "bending length (m)",
         "lambda / bending length", "depth (m)"), rows,
        note=f"The shipped scenes (deformable.scenes) with xi and the force model changed, {s['s5_t']:g} s (the rod "
             f"drawn over {scenes.config('curtain').draw_time:g} s). Folds: extrema of y along rows at "
             f"{', '.join(f'{100 * v:.0f}' for v in ROWS)} % of the height, with hysteresis (module docstring of "
             "validation.studies.paper.folds); medians over the rows and over the snapshots of the last "
             f"{LATE:g} s. lambda = 2 x fold width; bending length = (D H / (mu g))^(1/4) "
             "(deformable.scenes.fold_wavelength, Cerda & Mahadevan 2003), D = 2 xi (variational) or xi (tpbf87); "
             "'narrowest, ever': over every snapshot (each 0.1 s) of the run, and where those narrower than "
             f"{NARROWEST:g} h sit along a1 (the rod is drawn from a1 = L1); h: the grid spacing along a1."))
    series_rows = [(k[1], k[2].upper(), k[3], k[4], p["t"], p["count"], p["width"] / R[k]["h"],
                    p["narrowest"] / R[k]["h"], p["ptp"]) for k in runs.keys for p in F[k]["series"]]
    res.tables.append(Table("folds_over_time", "Section 5: the folds over time (every 0.1 s)",
                            ("scene", "backend", "force model", "xi (N m)", "t (s)", "folds", "fold width (h)",
                             "narrowest (h)", "largest peak-to-peak (m)"), series_rows,
                            note="The fold measure of every snapshot (medians over the rows; the narrowest over all "
                                 f"rows). Before the folds grow past the hysteresis ({1e3 * DELTA_MIN:g} mm) a row has "
                                 "none."))


def _sweep_checks(res, runs: FoldRuns) -> dict:
    """The energy-consistent runs stay bounded; the fold wavelength and count against xi over the curtain's sweep.
    Returns the fits, {backend: dict(p, p_wavelength, p_wavelength_se, counts, prefactor, spread)}."""
    R = runs.R
    res.check_all("section 5, curtain folds: the energy-consistent runs stay bounded",
                  "every run of the shipped curtain scenes finishes, with no fibre stretched past twice its length",
                  {f"{k[1]} {k[2].upper()} xi = {k[4]:g}": R[k]["status"] == "finished" and classify(R[k]) == "bounded"
                   for k in runs.var})
    fits = {}
    for b in BACKENDS:
        sweep = runs.sweep[b]
        xis = [xi for xi, _ in sweep]
        counts = [f["count"] for _, f in sweep]
        lams = [f["wavelength"] for _, f in sweep]
        ok_w, obs_w, pw, se_w = wavelength_exponent(xis, lams)
        ok_c, obs_c, p = count_exponent(xis, counts)
        pref = [f["prefactor"] for _, f in sweep if np.isfinite(f["prefactor"])]
        C = float(np.exp(np.mean(np.log(pref)))) if pref else math.nan
        fits[b] = dict(p=p, p_wavelength=pw, p_wavelength_se=se_w, counts=counts, prefactor=C,
                       spread=(min(pref), max(pref)) if pref else (math.nan,) * 2)
        lo, hi = WAVELENGTH_WINDOW
        where = (f"{len(xis)} values of xi from {min(xis, default=math.nan):g} to {max(xis, default=math.nan):g} N m, "
                 f"{runs.grid(b)}")
        res.check(f"section 5, curtain folds: {b.upper()} fold wavelength against xi",
                  f"lambda ~ xi^p with p in [{lo:g}, {hi:g}] around the bending-length theory's 1/4, its standard "
                  f"error at most {(hi - lo) / 2:.2f} ({where})", obs_w, ok_w)
        lo, hi = EXPONENT_WINDOW
        res.check(f"section 5, curtain folds: {b.upper()} fold count against xi",
                  f"count ~ xi^p with p in [{lo:g}, {hi:g}] around the theory's -1/4, fitted only to counts that "
                  f"take at least {COUNT_SPAN[0]} values with the largest at least {COUNT_SPAN[1]:g} times the "
                  f"smallest ({where})", obs_c, ok_c)
    return fits


def _narrowest_checks(res, runs: FoldRuns) -> None:
    """No fold of the curtain's sweep narrower than :data:`NARROWEST` grid spacings, ever; the energy-consistent
    runs outside the sweep that have one, as a finding."""
    F, swept = runs.F, runs.swept
    ok_n, obs_n = narrowest_check({f"{k[2].upper()} xi = {k[4]:g}": F[k]["ever_narrowest_h"] for k in sorted(swept)},
                                  NARROWEST)
    below = [f"{k[2].upper()} xi = {k[4]:g} below {NARROWEST:g} h in {F[k]['below']} of {len(F[k]['series'])} "
             f"snapshots, at a1 = {F[k]['below_at'][0]:.2f} to {F[k]['below_at'][1]:.2f} m" for k in sorted(swept)
             if F[k]["below"]]
    swept_runs = ", ".join(sorted({runs.grid(k[2]) for k in swept})) + "; xi = " + ", ".join(
        f"{x:g}" for x in sorted({k[4] for k in swept}))
    res.check(f"section 5, curtain folds: never narrower than {NARROWEST:g} grid spacings",
              f"the narrowest fold (consecutive extrema) over every row of every snapshot (each {SAMPLE_EVERY:g} s) "
              f"at least {NARROWEST:g} h wide, in each of the {len(swept)} energy-consistent runs of the curtain's xi "
              f"sweep ({swept_runs}); curtain-silky and paper: the check below", obs_n + (
                  f" ({'; '.join(below)})" if below else ""), ok_n)
    narrow = [k for k in runs.var if k not in swept and np.isfinite(F[k]["ever_narrowest_h"])
              and not at_least(F[k]["ever_narrowest_h"], NARROWEST)]
    if narrow:
        cfg = scenes.config("curtain")
        res.findings.append(
            f"Section 5, folds narrower than {NARROWEST:g} grid spacings outside the curtain's sweep, over every "
            f"snapshot (the Figs 5-6 check tests those of the last {LATE:g} s): "
            + "; ".join(f"{k[1]} {k[2].upper()} xi = {k[4]:g}: {F[k]['count']:g} folds, narrowest "
                        f"{F[k]['ever_narrowest_h']:.1f} h at a1 = {F[k]['below_at'][0]:.2f} to "
                        f"{F[k]['below_at'][1]:.2f} m, median fold width {F[k]['width_h']:.1f} h, bending length "
                        f"{F[k]['theory']:.3f} m = {F[k]['theory'] / runs.R[k]['h']:.1f} h" for k in sorted(narrow))
            + f". The rod's drawn end gathers the cloth over a1 = {(1 - cfg.gather) * cfg.size[0]:g} to "
            f"{cfg.size[0]:g} m; docs/design.md (Findings) has the folds under refinement.")


def _agreement_check(res, runs: FoldRuns) -> None:
    """FD and FE fold wavelengths agree over the curtain's sweep."""
    swept, agree = runs.swept, {}
    for k in swept:
        if k[2] != "fd":
            continue
        other = ("folds", k[1], "fe", k[3], k[4])
        if other in swept:
            ld, le = swept[k]["wavelength"], swept[other]["wavelength"]
            agree[f"xi = {k[4]:g} (lambda FD {ld:.3g} m, FE {le:.3g} m; counts {swept[k]['count']:g}, "
                  f"{swept[other]['count']:g})"] = bool(abs(ld - le) <= COUNT_TOLERANCE * max(ld, le))
    res.check_all("section 5, curtain folds: FD and FE fold wavelengths agree",
                  f"late fold wavelengths within {COUNT_TOLERANCE:.0%} of the larger for each xi of the curtain's "
                  "sweep (the wavelength, not the count: counts of 1 to 3 always agree within one fold)", agree)


def _sheet_checks(res, runs: FoldRuns) -> None:
    """Figs 5-6 as the paper describes them: light (silky) and stiff (paper) sheets with little stretching, and
    their folds resolved."""
    F, sheets = runs.F, runs.sheets
    at_1s = {k: min(r["stretch"], key=lambda m: abs(m[0] - STRETCH_TIME)) for k, r in sheets.items() if r["stretch"]}
    res.check_all(f"section 5, Figs 5-6: little stretching at t = {STRETCH_TIME:g} s",
                  f"curtain-silky and paper on their grids, both backends: median fibre stretch <= "
                  f"{STRETCH_MEDIAN:.0%}, largest <= {STRETCH_LARGEST:.0%} (every grid segment against its rest "
                  "length)",
                  {f"{k[1]} {k[2].upper()} (median {m[1]:.2%}, largest {m[2]:.2%} at t = {m[0]:g} s)":
                   abs(m[0] - STRETCH_TIME) < 1e-6 + SAMPLE_EVERY / 2 and m[1] <= STRETCH_MEDIAN
                   and m[2] <= STRETCH_LARGEST
                   for k, m in at_1s.items()} if len(at_1s) == len(sheets) else {})
    ok_s, obs_s = narrowest_check({f"{k[1]} {k[2].upper()}": F[k]["narrowest_h"] for k in sorted(sheets)}, NARROWEST)
    grids = ", ".join(sorted({runs.grid(k[2], k[1]) for k in sheets}))
    res.check(f"section 5, Figs 5-6: folds at least {NARROWEST:g} grid spacings wide",
              f"curtain-silky and paper at their own xi ({grids}): "
              f"the narrowest fold over every row of the snapshots of the last {LATE:g} s at least {NARROWEST:g} h "
              "wide", obs_s, ok_s)
    res.data["stretch"] = {"|".join(map(str, k)): runs.R[k]["stretch"] for k in sheets}


def _ratio_check(res, runs: FoldRuns) -> tuple[dict, dict]:
    """Paper against curtain-silky: the ratio of their fold wavelengths against the theory's. Returns the measured
    and the expected ratios by backend."""
    ratio, expected = {}, {}
    for b in BACKENDS:
        silky = runs.var.get(("folds", "curtain-silky", b, "variational", scenes.config("curtain-silky").xi))
        paper = runs.var.get(("folds", "paper", b, "variational", scenes.config("paper").xi))
        if silky and paper:
            ratio[b] = paper["wavelength"] / silky["wavelength"]
            expected[b] = paper["theory"] / silky["theory"]
    xr = theory_ratio() ** 4  # (D / mu) of paper over the silky curtain's (their warps')
    lo, hi = xr ** -EXPONENT_WINDOW[1], xr ** -EXPONENT_WINDOW[0]
    res.check_all("section 5, paper against curtain-silky: fold wavelength ratio",
                  f"lambda(paper) / lambda(curtain-silky) in [{lo:.2f}, {hi:.2f}] = {xr:.3g}^p for p in the exponent "
                  f"window, {xr:.3g} = (xi / mu) of paper over the silky curtain's (theory: {xr:.3g}^(1/4) = "
                  f"{xr ** 0.25:.3g})",
                  {f"{b.upper()} ({ratio[b]:.2f})": lo <= ratio[b] <= hi and np.isfinite(ratio[b]) for b in ratio})
    return ratio, expected


def _findings(res, runs: FoldRuns, fits: dict, ratio: dict, expected: dict) -> None:
    """The folds' numbers (results.json), the fits against the theory and the curtain under the paper's force."""
    F = runs.F
    res.data["folds"] = dict(fits=fits, ratio=ratio, expected_ratio=expected,
                             runs={"|".join(map(str, k)): {x: F[k][x] for x in ("count", "width", "wavelength",
                                                                                  "theory",
                                                                                  "prefactor", "narrowest_h",
                                                                                  "ever_narrowest_h")}
                                   for k in runs.keys})
    for b in BACKENDS:
        f = fits[b]
        res.findings.append(
            f"Section 5, curtain folds ({runs.grid(b)}): lambda ~ xi^{f['p_wavelength']:.2f} +- "
            f"{f['p_wavelength_se']:.2f} (theory 1/4); counts {', '.join(format(c, 'g') for c in f['counts'])}"
            + (f" ~ xi^{f['p']:.2f} (theory -1/4)" if np.isfinite(f["p"]) else " (too few distinct to fit)")
            + f"; lambda = {f['prefactor']:.2f} x (D H / (mu g))^(1/4) "
            f"(geometric mean over the sweep; from {f['spread'][0]:.2f} to {f['spread'][1]:.2f}); paper / silky "
            f"wavelength ratio {ratio.get(b, math.nan):.2f} (theory {expected.get(b, math.nan):.2f}).")
    res.findings.append(
        "Section 5, the curtain under the paper's force (14), the same scene otherwise: "
        + "; ".join(f"{k[2].upper()} xi = {k[4]:g}: {classify(r)} (t = {r['t']:.3g} s, step {r['steps']}, max G_ii "
                    f"{r['Gmax']:.2f}), {f['count']:g} folds, narrowest {f['ever_narrowest_h']:.1f} h, fold width "
                    f"{f['width_h']:.1f} h, depth {f['depth']:.3f} m" for k, (r, f) in sorted(runs.paper_force.items()))
        + ". At xi = 0 the force has no bending stiffness and nothing sets a fold width; at xi > 0 its bending "
        "stiffness xi B is negative where B < 0 (claim 3; docs/design.md, 'Three readings').")


#: the lines of the fold figures, by (backend, force model): (matplotlib style, colour)
STYLE = {("fd", "variational"): ("o-", "tab:blue"), ("fe", "variational"): ("s-", "tab:orange"),
         ("fd", "tpbf87"): ("o--", "tab:cyan"), ("fe", "tpbf87"): ("s--", "tab:red")}


def _figures(res, runs: FoldRuns, fits: dict) -> None:
    """The figures: count and lambda against xi, the theory beside; the count over time."""
    count_lines, lambda_lines = _xi_lines(runs)
    F = runs.F
    th = np.array([min(f["theory"] for f in F.values() if f["theory"] > 0),
                   max(f["theory"] for f in F.values() if f["theory"] > 0)])
    C = fits["fd"]["prefactor"]
    if np.isfinite(C):
        lambda_lines.append(dict(x=th, y=C * th, style=":", color="0.3",
                                 label=f"lambda = {C:.2f} x bending length (FD fit)"))
    time_lines = []
    for k in sorted(runs.var):
        ser = F[k]["series"]
        time_lines.append(dict(x=[p["t"] for p in ser], y=[p["count"] for p in ser],
                               style="-" if k[2] == "fd" else "--",
                               label=f"{k[1]} {k[2].upper()} xi={k[4]:g}"))
    res.figures.append(Figure("folds_xi", "Section 5: the curtain's folds against xi (left) and its fold wavelength "
                              "against the bending length (D H / (mu g))^(1/4) (right), FD and FE, both force models",
                              image=panels_figure([
                                  dict(title="fold count (late median) against xi", xlabel="xi (N m)",
                                       ylabel="fold count (1)", lines=count_lines, xlog=True, integer=True),
                                  dict(title="fold wavelength against the bending length", xlabel="bending length (m)",
                                       ylabel="lambda = 2 x fold width (m)", lines=lambda_lines, xlog=True, ylog=True)],
                                  "Folds of the drawn curtain", width=5.2, height=4.2)))
    res.figures.append(Figure("folds_time", "Section 5: fold count over time, energy-consistent runs (FD solid, FE "
                              "dashed); the rod is drawn until t = "
                              f"{scenes.config('curtain').draw_time:g} s",
                              image=panels_figure([dict(title="folds (median over rows)", xlabel="t (s)",
                                                        ylabel="fold count (1)", lines=time_lines, integer=True)],
                                                 "Folds over time", width=8.0, height=4.2)))


def _xi_lines(runs: FoldRuns) -> tuple[list, list]:
    """The lines of the curtain's count against xi (with the theory's slope) and of every run's lambda against its
    bending length."""
    F, keys = runs.F, runs.keys
    count_lines, lambda_lines = [], []
    for b in BACKENDS:
        for fm in ("variational", "tpbf87"):
            pts = sorted((k[4], F[k]) for k in keys if k[1] == "curtain" and k[2] == b and k[3] == fm
                         and k[4] > 0)  # log axes: xi = 0 (and its bending length 0) in the tables only
            st, col = STYLE[(b, fm)]
            count_lines.append(dict(x=[x for x, _ in pts], y=[f["count"] for _, f in pts], label=f"{b.upper()} {fm}",
                                    style=st, color=col))
            lambda_lines.append(dict(x=[f["theory"] for _, f in pts], y=[f["wavelength"] for _, f in pts],
                                     label=f"{b.upper()} {fm}", style=st, color=col))
        counts = [f["count"] for _, f in runs.sweep[b] if f["count"] > 0]
        if counts:  # the theory's slope through the centre of the measured counts
            xs = np.array(runs.s["fold_xis"], float)
            centre = np.exp(np.mean(np.log(xs)))
            count_lines.append(dict(x=xs, y=np.exp(np.mean(np.log(counts))) * (xs / centre) ** -0.25, style=":",
                                    color=STYLE[(b, "variational")][1], label=f"{b.upper()}: slope -1/4 (theory)"))
    for sc in ("curtain-silky", "paper"):
        for b in BACKENDS:
            k = ("folds", sc, b, "variational", scenes.config(sc).xi)
            if k in F:
                lambda_lines.append(dict(x=[F[k]["theory"]], y=[F[k]["wavelength"]], label=f"{sc} {b.upper()}",
                                         style="^" if sc == "paper" else "v", color=STYLE[(b, "variational")][1]))
    return count_lines, lambda_lines


def _stop(v: dict) -> str:
    """How a run stopped: 'diverged in its first step', or 'diverged at t = ... s (n steps)'."""
    return (f"{v['status']} in its first step" if v["t"] <= 0 else
            f"{v['status']} at t = {v['t']:.3g} s ({v['steps']} steps)")


def curtain_claim(fits: dict, ratio: dict, paper: dict) -> dict:
    """Figs 3-6's claim, judged from what was measured.

    ``fits``: {backend: dict(p_wavelength, p_wavelength_se, counts)} of the energy-consistent xi sweep; ``ratio``:
    {backend: lambda(paper) / lambda(curtain-silky)}; ``paper``: {(backend, xi): dict(status, t (s), steps,
    Gmax, count, narrowest_h (grid spacings, every snapshot), width_h)} of the curtain under the paper's force
    (14). A paper-force run that finished judges the claim (the curtain folds, resolved: its narrowest fold at
    least :data:`NARROWEST` spacings); one that diverged judges nothing and is named in ``not_judged``, as is
    Fig. 6's xi = 3e-6, which this section does not run (claim 4 measures its effect on the motion). Returns
    literal, measured, holds_when, not_judged (texts for :class:`~validation.studies.paper.claims.Claim`).
    """
    def fit(b):
        f = fits[b]
        return f"xi^{f['p_wavelength']:.2f} +- {f['p_wavelength_se']:.2f} ({b.upper()})"

    finished = {k: v for k, v in sorted(paper.items()) if v["status"] == "finished"}
    stopped = {k: v for k, v in sorted(paper.items()) if v["status"] != "finished"}
    resolved = {k: at_least(v["narrowest_h"], NARROWEST) for k, v in finished.items()}  # NaN (no fold pair): False

    def run(k, v):
        return (f"{k[0].upper()} xi = {k[1]:g}: {v['count']:g} folds, fold width {v['width_h']:.1f} h, narrowest "
                f"{v['narrowest_h']:.1f} h")

    measured = (f"lambda ~ {', '.join(fit(b) for b in fits)} against 1/4 (counts "
                + "; ".join(f"{', '.join(format(c, 'g') for c in fits[b]['counts'])} ({b.upper()})" for b in fits)
                + "); paper / silky lambda " + ", ".join(f"{v:.2f} ({b.upper()})" for b, v in ratio.items())
                + f" against the theory's {theory_ratio():.2f}; under the paper's force: "
                + ("; ".join([run(k, v) for k, v in finished.items()]
                             + [f"{k[0].upper()} xi = {k[1]:g} {_stop(v)}" for k, v in stopped.items()]) or "not run"))
    holds_when = "under the energy-consistent force, with xi > 0 (folds follow the bending length)"
    flat = [run(k, v) for k, v in finished.items() if not resolved[k]]
    if flat:
        holds_when += (f"; under the paper's force (14) at {'; '.join(flat)}: folds at the grid scale, not resolved "
                       "(nothing in it sets a fold width)")
    not_judged = ("Fig. 6's xi = 3e-6 (not run in this section: claim 4 has its effect on the motion)"
                  + (f"; the paper's force (14) at {', '.join(f'{k[0].upper()} xi = {k[1]:g}' for k in stopped)}: "
                     f"stopped by t = {max(v['t'] for v in stopped.values()):.3g} s, before any fold; no conclusion "
                     "on its folds there" if stopped else ""))
    return dict(literal=bool(finished) and all(resolved.values()), measured=measured, holds_when=holds_when,
                not_judged=not_judged)
