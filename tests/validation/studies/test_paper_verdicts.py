"""The paper study's verdicts say what was measured: each check computed from its data, on small inputs.

- section 3.1: "gamma = 0 keeps oscillating" from the measured roots, per scheme, with the loss a period;
- Figs 7-8: a run under the paper's force that stops before the analysis window judges nothing, and is named;
- Figs 3-6: the fold wavelength's exponent with its standard error, the fold count's refused where the counts
  span too little, the narrowest fold (not the median) against 3 grid spacings, a check over no run fails;
- a claim with an unjudged case says so in its verdict.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from validation.harness.study import StudyResult
from validation.studies.paper import damping, flag, folds
from validation.studies.paper.claims import Claim


def _entries(steps: int = 64) -> dict:
    """data["damping"]-shaped undamped entries: the schemes' own roots at w0 = 10 rad/s, ``steps`` a period."""
    w0 = 10.0
    dt = 2 * math.pi / (w0 * steps)
    return {f"{b}|undamped|{sc}": dict(w0=w0, dt=dt, z=[damping.scheme_root(sc, w0, 0.0, dt).real,
                                                         damping.scheme_root(sc, w0, 0.0, dt).imag])
            for b in ("fd", "fe") for sc in damping.SCHEMES}


def test_gamma_zero_keeps_its_amplitude_only_under_the_trapezoidal_rule():
    u = damping.undamped_claim(_entries(64))
    # the paper's step at gamma = 0: |z| = (1 + (w dt)^2)^(-1/2), over the 2 pi / arg z steps of a period
    z = damping.scheme_root("semi-implicit", 10.0, 0.0, 2 * math.pi / 640)
    assert u["kept"][("fd", "semi-implicit")] == pytest.approx(abs(z) ** (2 * math.pi / abs(np.angle(z))))
    assert 0.72 < u["kept"][("fd", "semi-implicit")] < 0.75  # 26.5 % lost a period at 64 steps
    assert u["kept"][("fe", "newmark")] == pytest.approx(1.0, abs=1e-12)
    assert u["keeps"] == {(b, sc): sc == "newmark" for b in ("fd", "fe") for sc in damping.SCHEMES}
    assert u["literal"] is False
    assert "26.5 % (FD)" in u["measured"] and "Newmark's trapezoidal rule, which keeps the amplitude" in u["holds_when"]
    assert "under implicit Euler and the paper's semi-implicit step" in u["holds_when"]


def test_gamma_zero_keeps_oscillating_under_every_scheme_once_the_step_is_small():
    u = damping.undamped_claim(_entries(20000))  # loss ~ 1 - exp(-pi w dt) = 0.1 % a period: within LOSS_KEPT
    assert u["literal"] is True and all(u["keeps"].values())
    assert damping.undamped_claim({})["literal"] is False  # nothing measured: not shown to hold


def test_the_amplitude_kept_a_period_is_exp_of_minus_rate_times_period():
    z = 0.99 * np.exp(1j * 0.1)
    assert damping.amplitude_per_period(z, 0.01) == pytest.approx(0.99 ** (2 * math.pi / 0.1))
    assert math.isnan(damping.amplitude_per_period(0.9 + 0j, 0.01))  # no oscillation, no period


def _flag_run(status: str, t_end: float, k: float, frequency: float = 4.0, Gmax: float = 1.2) -> dict:
    a = np.linspace(0.0, 1.2, 13)
    t = np.arange(0.0, t_end + 1e-9, 5e-3)
    line = np.sin(math.pi * a / 2.4) * np.cos(2 * math.pi * frequency * t[:, None] - k * a)
    return dict(status=status, t=float(t[-1]), dt=5e-3, Gmax=Gmax, a=a, line_t=t, line=line,
                config=dict(ramp=0.5, frequency=frequency, xi=1e-5, size=(1.2, 0.8)))


def test_a_paper_force_run_that_diverged_is_not_judged_and_says_why():
    wave = flag.run_phase(_flag_run("finished", 2.0, 6.0), 2.0)
    assert wave.change > math.pi
    stopped = dict(status="diverged", t=0.81, Gmax=5.67, dt=9.1e-4, force_model="tpbf87")
    c = flag.paper_force_claim({"fd": wave, "fe": wave}, {("fd", 0.0): (None, stopped)}, (1.0, 2.0))
    assert c["literal"] is True
    assert "FD xi = 0" in c["not_judged"] and "no conclusion" in c["not_judged"]
    assert "max G_ii 5.67" in c["measured"] and "claim 3a" in c["not_judged"]
    verdict = Claim("flag", "5", c["measured"], literal=c["literal"], checks=(True,), holds_when=c["holds_when"],
                    not_judged=c["not_judged"]).verdict
    assert verdict.startswith("holds where measured (under the energy-consistent force); not judged under the paper's")
    assert "does not give it" not in verdict


def test_a_paper_force_run_that_does_not_wave_makes_the_claim_false():
    wave = flag.run_phase(_flag_run("finished", 2.0, 6.0), 2.0)
    flat = flag.run_phase(_flag_run("finished", 2.0, 0.5), 2.0)
    c = flag.paper_force_claim({"fd": wave}, {("fd", 0.0): (flat, dict(status="finished", t=2.0))}, (1.0, 2.0))
    assert c["literal"] is False and c["not_judged"] == ""
    assert "FD xi = 0" in c["holds_when"] and "less than pi" in c["holds_when"]


def test_the_flag_section_tables_every_paper_force_run_and_names_the_stopped_ones():
    R = {("flag", b, "variational"): _flag_run("finished", 2.0, 6.0) for b in ("fd", "fe")}
    for b in ("fd", "fe"):
        for key, xi in (((("flag", b, "tpbf87")), 1e-5), (("flag", b, "tpbf87", 0.0), 0.0)):
            r = _flag_run("diverged", 0.5, 6.0, Gmax=4.5)
            r["config"] = dict(r["config"], xi=xi)
            R[key] = r
    res = StudyResult("paper", "test")
    (claim,) = flag.measure(res, R, dict(s5=(13, 7), s5_t=2.0))
    assert all(c.passed for c in res.checks), [(c.name, c.observed) for c in res.checks]
    assert len(res.tables[0].rows) == 6
    assert claim.verdict.startswith("holds where measured")
    assert "FD xi = 0, FD xi = 1e-05, FE xi = 0, FE xi = 1e-05" in claim.verdict


def test_the_wavelength_exponent_comes_with_its_standard_error():
    xi = np.array([1e-4, 3e-4, 1e-3])
    ok, text, p, se = folds.wavelength_exponent(xi, 6.0 * (2 * xi * 1.2 / (0.2 * 9.81)) ** 0.25)
    assert ok and p == pytest.approx(0.25) and se == pytest.approx(0.0, abs=1e-12) and "+- 0.000" in text
    ok, text, p, se = folds.wavelength_exponent(xi, [0.635, 0.905, 0.968])  # FD 64 x 64, the committed run
    assert ok and p == pytest.approx(0.181, abs=1e-3) and se == pytest.approx(0.077, abs=1e-3)
    assert not folds.wavelength_exponent(xi, [0.5, 0.6, 2.0])[0]  # 0.55: outside [0.12, 0.4]
    assert not folds.wavelength_exponent(xi, [0.5, 1.2, 0.55])[0]  # in the window, but its error spans it
    ok, text, *_ = folds.wavelength_exponent(xi, [0.6, math.nan, 0.9])
    assert not ok and text.startswith("not measurable: 2 run(s)")


def test_a_count_exponent_is_not_fitted_to_counts_that_differ_by_one_fold():
    xi = [1e-4, 3e-4, 1e-3]
    ok, text, p = folds.count_exponent(xi, [2, 2, 1])
    assert not ok and math.isnan(p) and text.startswith("not measurable: counts 2, 2, 1")
    assert not folds.count_exponent(xi, [3, 2, 2])[0]  # 2 distinct values
    assert not folds.count_exponent(xi, [5, 4, 3])[0]  # 3 distinct, but 5 / 3 < 2
    ok, text, p = folds.count_exponent([1e-5, 1e-4, 1e-3], [6, 4, 2])
    assert ok and p == pytest.approx(-0.239, abs=1e-3) and text.startswith("p = -0.239")


def test_the_narrowest_fold_decides_and_no_run_is_no_pass():
    ok, text = folds.narrowest_check({"curtain-silky FD": 1.0, "paper FD": 5.0, "paper FE": 6.75}, folds.NARROWEST)
    assert not ok and text.startswith("2 of 3 hold") and text.endswith("not: curtain-silky FD")
    assert folds.narrowest_check({"FD xi = 0.0001": 5.0, "FE xi = 0.0001": 3.75}, 3.0)[0]
    assert folds.narrowest_check({"FE": math.nan}, 3.0) == (False, "0 of 1 hold (FE nan h); not: FE")
    assert folds.narrowest_check({}, 3.0) == (False, "no run to check")


def test_the_curtain_claim_names_the_paper_force_runs_that_diverged():
    fits = {b: dict(p_wavelength=0.18, p_wavelength_se=0.08, counts=[2.0, 2.0, 1.0]) for b in ("fd", "fe")}
    paper = {("fd", 0.0): dict(status="finished", t=2.0, steps=3572, Gmax=1.4, count=17.5, narrowest_h=1.0,
                               width_h=2.6),
             ("fd", 1e-4): dict(status="diverged", t=0.00112, steps=2, Gmax=1.03, count=0.0, narrowest_h=math.nan,
                                width_h=math.nan)}
    c = folds.curtain_claim(fits, {"fd": 1.63, "fe": 1.10}, paper)
    assert c["literal"] is False  # the paper's force at xi = 0 folds at the grid scale
    assert "FD xi = 0: 17.5 folds" in c["holds_when"] and "not resolved" in c["holds_when"]
    assert "FD xi = 0.0001" in c["not_judged"] and "no conclusion" in c["not_judged"]
    assert "xi = 3e-6" in c["not_judged"]


def test_a_verdict_names_what_no_run_judged():
    assert Claim("s", "5", "m", literal=True, checks=(True,), holds_when="under A",
                 not_judged="under B: diverged").verdict == \
        "holds where measured (under A); not judged under B: diverged"
    assert Claim("s", "5", "m", literal=False, checks=(True,), holds_when="under A",
                 not_judged="under B").verdict == "false as stated; holds only under A; not judged under B"
    assert Claim("s", "5", "m", literal=None, checks=(True,), not_judged="no run finished").verdict == \
        "not judged: no run finished"
    assert Claim("s", "5", "m", literal=True, checks=(True,), not_judged="x").verdict.startswith("holds where measured")


def _curtain_run(scene: str, backend: str, fm: str, xi: float, half_waves: int, finished: bool = True) -> dict:
    """A recorded run of the shape cases._run_shipped gives: rows of y = sine with ``half_waves`` half-waves."""
    from deformable import scenes

    cfg = scenes.config(scene)
    nodes = 17
    a = np.linspace(0.0, cfg.size[0], 4 * (nodes - 1) + 1)
    t = np.arange(0.0, 2.0 + 1e-9, 0.1) if finished else np.array([0.0])
    row = 0.05 * np.sin(half_waves * math.pi * a / cfg.size[0])
    rows = np.broadcast_to(row, (t.size, len(folds.ROWS), a.size)).copy()
    return dict(status="finished" if finished else "diverged", t=float(t[-1]) if finished else 0.0, steps=400 if
                finished else 0, dt=5e-3, h=cfg.size[0] / (nodes - 1), Gmax=1.1, a=a, rows=rows, rows_t=t,
                stretch=[(1.0, 0.001, 0.01)],
                config=dict(xi=xi, mu=cfg.mu, scale=cfg.scale, g=cfg.g, size=cfg.size, force_model=fm))


def test_the_folds_section_checks_the_wavelength_refuses_the_counts_and_names_unjudged_runs():
    from deformable import scenes

    s = dict(folds=(17, 17), silky=(17, 17), s5_t=2.0, fold_xis=(1e-4, 3e-4, 1e-3))
    R = {}
    for b in ("fd", "fe"):
        for xi, k in ((1e-4, 3), (3e-4, 2), (1e-3, 2)):  # widths L/3, L/2, L/2: counts 3, 2, 2
            R[("folds", "curtain", b, "variational", xi)] = _curtain_run("curtain", b, "variational", xi, k)
            R[("folds", "curtain", b, "tpbf87", xi)] = _curtain_run("curtain", b, "tpbf87", xi, k, finished=False)
        R[("folds", "curtain", b, "tpbf87", 0.0)] = _curtain_run("curtain", b, "tpbf87", 0.0, 15)
        for sc, k in (("curtain-silky", 4), ("paper", 3)):
            R[("folds", sc, b, "variational", scenes.config(sc).xi)] = _curtain_run(sc, b, "variational",
                                                                                   scenes.config(sc).xi, k)
    res = StudyResult("paper", "test")
    (claim,) = folds.measure(res, R, s)
    checks = {c.name: c for c in res.checks}
    count = checks["section 5, curtain folds: FD fold count against xi"]
    assert not count.passed and count.observed.startswith("not measurable: counts 3, 2, 2")
    wl = checks["section 5, curtain folds: FD fold wavelength against xi"]
    assert "+-" in wl.observed and "3 points" in wl.observed
    never = checks["section 5, curtain folds: never narrower than 3 grid spacings"]
    assert never.passed and "FD xi = 0.0001" in never.observed and "6 energy-consistent runs" in never.expectation
    # 15 half-waves over 16 spacings: the paper-force run at xi = 0 folds ~1 spacing wide, tabled, not checked
    assert "narrowest" in checks["section 5, Figs 5-6: folds at least 3 grid spacings wide"].expectation
    assert "not shown" in claim.verdict  # the count checks fail
    assert "FD xi = 0:" in claim.measured and "diverged in its first step" in claim.measured
