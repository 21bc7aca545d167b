"""Whether a grid resolves a curtain's folds (``deformable params``): the narrowest fold, as the paper study measures.

The rule (deformable/scenes/params.py): the narrowest fold predicted is NARROWEST_PER_FOLD_SCALE x the fold scale
l_f = (D H / (mu g))^(1/4) (Cerda and Mahadevan 2003), resolved when at least RESOLVED = 3 grid spacings, i.e. l_f
at least FOLD_SCALE_SPACINGS = 4.5 spacings (measured on the drawn curtain, FD 32 to 80 nodes). A curtain in a
named fabric ships on the grid the rule says resolves it. The runs below are measured by the paper study's own fold
measure (validation/studies/paper/folds.py: extrema along its rows, the narrowest over the last 0.4 s).
"""

import math

import pytest

from deformable import scenes
from deformable.scenes.curtain import FABRIC_GRIDS
from deformable.scenes.params import FOLD_SCALE_SPACINGS, NARROWEST_PER_FOLD_SCALE, RESOLVED, parameters
from validation.commands import main
from validation.harness.backends import make_model


#: the curtain before the named fabrics (mu 0.2 kg/m^2, eta 20 N/m, xi 1e-4 N m, isotropic), on which the rule was
#: measured; xi = 1e-5 with it is the limp cloth
PLAIN = dict(fabric="", mu=0.2, eta=20.0, xi=1e-4, shear=1.0)


def _params(name="curtain", **fields):
    cfg = scenes.config(name, **fields)
    return cfg, parameters(cfg, make_model(scenes.build(cfg), "fd"), "fd")


def _narrowest(**fields) -> tuple[float, float]:
    """The narrowest fold (m) over the late snapshots of a run of the shipped curtain (FD, its t_end), recorded and
    measured as the paper study does, and its grid spacing h (m)."""
    from validation.studies.paper.cases import Case, _run_shipped, fields as case_fields
    from validation.studies.paper.folds import fold_series, late_folds

    cfg = scenes.config("curtain", **fields)
    n = cfg.nodes[0]
    rest = {k: v for k, v in fields.items() if k != "nodes"}
    r = _run_shipped(Case("scene", "curtain", "fd", n, case_fields(**rest), t_end=cfg.t_end))
    assert r["status"] == "finished"
    return late_folds(fold_series(r["a"], r["rows_t"], r["rows"]), r["t"])["narrowest"], r["h"]


def test_the_rule_is_the_narrowest_fold_at_least_3_spacings():
    """Its arithmetic: predicted narrowest = k l_f, resolved when >= 3 h; a limp cloth (xi = 1e-5) on the shipped
    64 x 64 is not resolved (l_f 3.7 h, measured: folds at 1 h on 48 x 48), the curtain before the fabrics is (l_f
    6.6 h, measured 12 h on 64 x 64), and so is the shipped curtain, denim, on the grid it ships on."""
    assert NARROWEST_PER_FOLD_SCALE == pytest.approx(RESOLVED / FOLD_SCALE_SPACINGS)
    cfg, limp = _params(**{**PLAIN, "xi": 1e-5})
    h = min(limp.spacing)
    assert cfg.nodes == (64, 64) and 3.5 < limp.fold_scale / h < 4.0
    assert limp.narrowest_fold == pytest.approx(NARROWEST_PER_FOLD_SCALE * limp.fold_scale, rel=1e-12)
    assert not limp.resolved
    line = limp.lines()[-1]
    assert f"narrowest fold predicted {NARROWEST_PER_FOLD_SCALE:.2g} x that" in line and "NOT resolved" in line
    assert f"{limp.narrowest_fold / h:.3g} grid spacings" in line and "resolved when at least 3" in line
    assert f"{limp.fold_scale / h:.3g} grid spacings (Cerda and Mahadevan 2003)" in line  # the old information
    assert _params(**PLAIN)[1].resolved
    cfg, denim = _params()
    assert cfg.fabric == "denim" and denim.resolved and "NOT" not in denim.lines()[-1]


def test_a_fabric_ships_on_the_coarsest_grid_that_resolves_it_and_explicit_nodes_win(capsys):
    for fabric, n in (("denim", 64), ("tablecloth", 64), ("jacket-polyester", 80), ("tshirt-knit", 96)):
        cfg, p = _params(fabric=fabric)
        assert cfg.nodes == (n, n) and p.resolved, fabric
        coarser = n - 16
        if coarser in FABRIC_GRIDS:  # the coarsest: one grid coarser is not resolved
            assert not _params(fabric=fabric, nodes=(coarser, coarser))[1].resolved, fabric
    assert scenes.config("curtain").nodes == (64, 64) and scenes.config("curtain-silky").nodes == (80, 80)
    assert scenes.config("curtain", fabric="denim", nodes=(32, 32)).nodes == (32, 32)  # the user's grid wins
    assert scenes.config("curtain", nodes=(40, 40)).replace(fabric="denim").nodes == (40, 40)  # set before: kept
    assert scenes.config("curtain", fabric="tshirt-knit").replace(fabric="").nodes == (64, 64)  # own grid back
    assert scenes.config("curtain", fabric="denim").replace(fabric="tshirt-knit").nodes == (96, 96)
    assert scenes.config("curtain", scale=20.0).nodes == (128, 128)  # scale 20: folds 20^(1/4) narrower
    assert main(["params", "curtain", "fabric=jacket-polyester"]) == 0
    assert capsys.readouterr().out.startswith("curtain: 80 x 80 nodes on fd")
    assert main(["params", "curtain", "fabric=jacket-polyester", "--grid", "32x32"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("curtain: 32 x 32 nodes on fd") and "NOT resolved" in out


@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
def test_a_run_the_rule_calls_unresolved_folds_narrower_than_3_spacings():
    """The limp cloth (xi = 1e-5, l_f 1.4 h) on FD 24 x 24, drawn in 0.8 s and measured over 0.6-1 s (the shipped
    schedule at twice its pace: 8 s on one core against 14 s; on it the narrowest late fold is 2 h as well):
    predicted NOT resolved, and its narrowest late fold is below 3 h (measured 2 h)."""
    fields = dict(PLAIN, xi=1e-5, nodes=(24, 24), draw_time=0.8, t_end=1.0)
    assert not _params(**fields)[1].resolved
    narrowest, h = _narrowest(**fields)
    assert math.isfinite(narrowest) and narrowest < RESOLVED * h


@pytest.mark.slow
def test_a_run_the_rule_calls_resolved_keeps_its_folds_at_least_3_spacings_wide():
    """The curtain before the fabrics (xi = 1e-4) on FD 48 x 48 (l_f 4.9 h, about 50 s on one core): predicted
    resolved, and its narrowest late fold is at least 3 h (measured 5 h)."""
    fields = dict(PLAIN, nodes=(48, 48))
    assert _params(**fields)[1].resolved
    narrowest, h = _narrowest(**fields)
    assert narrowest >= RESOLVED * h
