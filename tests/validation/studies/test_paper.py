"""Study ``paper``: its key physics at the coarsest settings (sections 3.1, 3.2 and the stability bound).

- scaling (mu, gamma, f) by a is the same trajectory as dividing (eta, xi) by a, to round-off;
- the frozen (alpha-direct) model stores alpha L1 L2 at rest with no load, eta/xi control nothing;
- a dt well above the stretching bound h sqrt(mu / (2 eta G)) blows up, well below it does not;
- a claim's verdict is computed from its checks, never written by hand.

The whole sweep runs under ``slow`` (it is not in the default ``deformable validate`` set either).
"""

import pytest

from validation.studies.paper import STUDY, classify, predictions, run_case, spectrum, trajectory_difference
from validation.studies.paper.cases import FROZEN, SCALE, VISIBLE, XI_BASE, Case, fields, paper_config
from validation.studies.paper.claims import Claim


@pytest.mark.parametrize("backend, nodes", [("fd", 8), ("fe", 5)])
def test_scaling_mu_gamma_f_equals_dividing_eta_xi(backend, nodes):
    base = paper_config("curtain")
    a, T = SCALE, 0.2

    def run(**kw):
        return run_case(Case("run", "curtain", backend, nodes, fields(**{"xi": XI_BASE, **kw}), t_end=T, every=10))

    P = run(mu=a * base.mu, gamma=a * base.gamma, push=a * base.push)
    Q = run(eta=base.eta / a, xi=XI_BASE / a)
    R = run(mu=a * base.mu, gamma=a * base.gamma, push=a * base.push, g=base.g)  # eta fixed: not the same
    assert P["status"] == Q["status"] == "finished"
    d = trajectory_difference(P, Q)
    assert d <= 1e-10, f"{backend}: (a mu, a gamma, a f) vs (eta/a, xi/a) differ by {d:.2e} (round-off expected)"
    ref = run()
    assert trajectory_difference(R, ref) >= VISIBLE  # with eta, xi fixed the motion changes


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_frozen_alpha_has_residual_energy_eta_control_none(backend):
    n = 6
    L1, L2 = FROZEN["size"]
    alpha = FROZEN["alpha"]
    fa = run_case(Case("frozen", backend=backend, nodes=n, tag="alpha"))
    if backend == "fe":
        expected = alpha * L1 * L2
    else:  # the pointwise difference rows cover L1 (L2 + h2) and (L1 + h1) L2
        expected = 0.5 * alpha * (L1 * (L2 + fa["h2"]) + (L1 + fa["h1"]) * L2)
    assert abs(fa["stretching"] / expected - 1) <= 1e-12, (fa["stretching"], expected)
    assert fa["force"] > 0 and fa["displacement"] > 1e-3  # the rest state is not an equilibrium
    fx = run_case(Case("frozen", backend=backend, nodes=n, tag="eta-xi"))
    assert fx["stretching"] + fx["bending"] == 0.0 and fx["force"] == 0.0
    assert fx["displacement"] <= 1e-10


def test_dt_above_the_stretching_bound_blows_up_below_does_not():
    nodes = 8
    cfg = paper_config("curtain", nodes=(nodes, nodes))
    spec = spectrum("fd", cfg.size, nodes)
    dt_c = predictions(spec, cfg.mu, cfg.eta, cfg.dt, 1.0)["dt_c"]
    h = min(cfg.size) / (nodes - 1)
    assert abs(dt_c / (h * (cfg.mu / (2 * cfg.eta)) ** 0.5) - 1) < 0.05  # FD: h sqrt(mu / (2 eta G))
    runs = {f: run_case(Case("run", "curtain", "fd", nodes, fields(xi=0.0), dt=f * dt_c, t_end=0.2))
            for f in (0.3, 3.0)}
    assert classify(runs[0.3]) == "bounded", runs[0.3]["status"]
    assert classify(runs[3.0]) != "bounded", runs[3.0]["status"]


def test_a_claims_verdict_follows_its_checks():
    claim = Claim("xi above 1e-3 is unstable", "5", "xi_c = 2e-4", literal=False, checks=(True, True),
                  holds_when="where the limit h^4 / dt^2 is 1e-3")
    assert claim.verdict == "false as stated; holds only where the limit h^4 / dt^2 is 1e-3"
    assert Claim("s", "3.1", "m", literal=True, checks=(True,)).verdict == "holds"
    assert Claim("s", "3.1", "m", literal=False, checks=(True,)).verdict == "false"
    assert Claim("s", "5", "m", literal=None, checks=(True,)).verdict.startswith("not judged")
    assert Claim("s", "3.1", "m", literal=True, checks=(True, False, False)).verdict.startswith(
        "not shown (2 of 3 checks failed)")
    assert Claim("s", "3.1", "m", literal=True).verdict == "not measured (no check)"
    assert Claim("s", "3.1", "m", literal=True, checks=(True,)).row() == ("s", "3.1", "m", "holds")


@pytest.mark.slow
def test_the_quick_paper_study_fails_only_the_checks_its_measurements_do_not_support():
    """The whole sweep at its quick level (about an hour on two cores). The checks that fail as measured (issue 45,
    the curtains in named fabrics): the fold counts (5, 4, 2, 1 on FD) fall faster with xi than the theory's
    xi^(-1/4), on FD and FE; FE 32 x 32 el. folds denim 2.75 grid spacings narrow once (params predicts it does not
    resolve denim); the silky curtain's drawn corner stretches 6.8 % on FE 40 x 40 el. at 1 s. The test holds the
    study to reporting these, and nothing else, as failed: the wavelength exponents and the paper / silky ratio
    pass, and the silky curtain's and paper's narrowest late folds are at least 3 grid spacings."""
    res = STUDY.run(STUDY.levels.minimum)
    failed = {c.name: c.observed for c in res.checks if not c.passed}
    allowed = {"section 5, curtain folds: FD fold count against xi",
               "section 5, curtain folds: FE fold count against xi",
               "section 5, curtain folds: never narrower than 3 grid spacings",
               "section 5, Figs 5-6: little stretching at t = 1 s"}
    assert set(failed) <= allowed, failed
    assert all(c.passed for c in res.checks if "fold wavelength" in c.name or "at least 3 grid spacings" in c.name)
    if "section 5, curtain folds: never narrower than 3 grid spacings" in failed:
        assert "FD" not in failed["section 5, curtain folds: never narrower than 3 grid spacings"].split("not:")[1]


def test_a_count_is_drawn_on_integer_ticks_of_a_linear_axis_and_legends_stay_off_the_data(monkeypatch):
    import matplotlib.pyplot as plt

    from validation.studies.paper.pictures import panels_figure

    drawn = []
    close = plt.close
    monkeypatch.setattr(plt, "close", lambda f=None: (drawn.append(f), close(f)))
    lines = [dict(x=[1e-6, 1e-5, 1e-4], y=[2.0, 1.5, 1.0], label=f"FD xi model {k}") for k in range(3)]
    png = panels_figure([dict(title="folds", xlabel="xi (N m)", ylabel="fold count (1)", lines=lines, xlog=True,
                              integer=True)], "folds")
    assert png[:4] == b"\x89PNG" and len(drawn) == 1
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = drawn[0]
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    ax = fig.axes[0]
    assert ax.get_yscale() == "linear" and ax.get_xscale() == "log"
    lo, hi = ax.get_ylim()
    ticks = [t for t in ax.get_yticks() if lo <= t <= hi]
    assert len(ticks) >= 2 and all(float(t).is_integer() for t in ticks)
    renderer = canvas.get_renderer()
    legend, box = ax.get_legend().get_window_extent(renderer), ax.get_window_extent(renderer)
    assert legend.x0 >= box.x1 - 1, "the legend covers the axes"
