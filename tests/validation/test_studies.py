"""Every study at its coarsest level count: its checks pass and the key orders match theory."""

import numpy as np
import pytest

from validation.orders import fit_order
from validation.study import STUDIES, get_study


def run(name, levels=None, **kw):
    st = get_study(name)
    res = st.function(levels or st.levels.minimum, **kw)
    failed = [f"{c.name}: expected {c.expectation}, observed {c.observed}" for c in res.checks if not c.passed]
    assert not failed, "\n".join(failed)
    return res


def test_registry_holds_every_study_in_order():
    get_study("tensors")
    assert list(STUDIES) == ["tensors", "modes", "statics", "cross", "time", "compatibility", "work", "variational",
                             "paper"]
    assert not STUDIES["paper"].in_default  # its sweep runs on its own: deformable validate paper


def test_tensors_orders_on_the_generic_monge_patch():
    res = run("tensors", surfaces=["monge", "sphere"])
    expect = {("fd", "nodes, interior", "B11"): 1, ("fd", "stencil centres", "G11"): 2,
              ("fe", "Gauss 4x4", "G12"): 3, ("fe", "Gauss 4x4", "B22"): 2, ("fe", "Gauss 2x2", "B11"): 3}
    for (b, loc, comp), theory in expect.items():
        d = res.data[f"{b}|monge|{loc}|{comp}"]
        p = fit_order(d["h"], d["max"])
        assert abs(p - theory) <= 0.3, f"{b} {comp} at {loc}: observed order {p:.2f}, theory {theory}"
    assert any(f.startswith("sphere (not checked") for f in res.findings)


def test_modes_orders():
    res = run("modes")
    for key, theory in (("fd|both", 2), ("fe|both", 4), ("fe|tpbf87 bending", 4)):
        d = res.data[key]
        p = fit_order(d["h"], d["error"])
        assert abs(p - theory) <= 0.3, f"{key}: observed order {p:.2f}, theory {theory}"
    assert res.data["fd|tpbf87 xi only"]["max_K"] == 0.0


def test_statics_orders():
    res = run("statics")
    assert abs(res.data["fd"]["order"] - 2) <= 0.3 and abs(res.data["fe"]["order"] - 4) <= 0.3, res.data


def test_cross_difference_shrinks():
    """FD and FE approach each other at every refinement (issue 4: hanging over three levels). No order
    is asserted: the hanging cloth's two pinned corners are point supports of a membrane, singular in the
    continuum, which holds both backends below their smooth-solution orders (reported in the study)."""
    res = run("cross")
    for scene in ("hanging", "flag"):
        d = res.data[f"{scene}|r|fd-fe"]
        assert len(d) >= 3 and all(b < a for a, b in zip(d, d[1:])), f"{scene}: FD-FE position differences {d}"


def test_time_order_is_one():
    res = run("time")
    for b in ("fd", "fe"):
        assert abs(res.data[b]["order"] - 1) <= 0.3, f"{b}: temporal order {res.data[b]['order']:.2f}"


def test_compatibility_orders_and_flags():
    res = run("compatibility", surfaces=["monge", "sphere"])
    assert res.data["incompatible_rest_state"]["gauss"] == pytest.approx(0.25, abs=1e-12)
    for src, theory in (("exact", 2), ("fe", 2), ("fd", 1)):
        rows = res.data[f"{src}|monge"]
        p = fit_order([r["h"] for r in rows], [r["codazzi"] for r in rows])
        assert abs(p - theory) <= 0.3, f"{src}: Codazzi residual order {p:.2f}, theory {theory}"


def test_work_errors_fall():
    res = run("work")
    assert np.all(np.diff(res.data["fe"]["error"]) < 0)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["tensors", "modes", "statics", "compatibility"])
def test_full_levels(name):
    run(name, get_study(name).levels.full)


def test_variational_study_curls_both_ways_and_reports_tpbf87():
    res = run("variational")
    for kappa in ("+2", "-2"):
        d = res.data[f"fd_arc_kappa_{kappa}"]
        p = fit_order(d["h"], d["error"])
        assert abs(p - 1) <= 0.3, f"curling strip kappa {kappa}: tip error order {p:.2f}, theory 1"
    tpbf87 = {row[0] + "|" + str(row[1]): row[2] for row in next(t for t in res.tables if t.name == "tpbf87").rows}
    assert tpbf87["+2|0.001"] == "diverged" and tpbf87["-2|0.0001"] == "finished"
