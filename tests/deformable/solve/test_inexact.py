"""The step test, lagged factorisations and preconditioned CG of Newton's method (deformable.solve.directions,
deformable.solve.krylov)."""

import numpy as np
import pytest
import scipy.sparse as sp

import deformable as dm
from deformable import scenes
from deformable.errors import InputError
from deformable.solve.krylov import forcing, pcg
from deformable.solve.newton import NewtonSettings
from validation.harness.backends import descriptor, make_model


def _laplacian(n):
    return sp.diags([-np.ones(n - 1), 2.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csr")


def test_pcg_solves_a_definite_system_to_its_tolerance():
    A = _laplacian(200) + 0.01 * sp.identity(200)
    b = np.random.default_rng(0).standard_normal(200)
    diag = A.diagonal()
    res = pcg(A, b, lambda r: r / diag, rtol=1e-8, maxiter=1000)
    assert res.status == "converged"
    assert np.linalg.norm(A @ res.x - b) <= 1e-8 * np.linalg.norm(b)


def test_pcg_with_the_exact_inverse_as_preconditioner_converges_in_one_product():
    A = (_laplacian(50) + sp.identity(50)).tocsc()
    lu = sp.linalg.splu(A)
    res = pcg(A, np.ones(50), lu.solve, rtol=1e-10, maxiter=5)
    assert res.status == "converged" and res.iterations == 1


def test_pcg_stops_on_negative_curvature_and_on_its_budget():
    A = -sp.identity(10, format="csr")
    assert pcg(A, np.ones(10), lambda r: r, maxiter=5).status == "indefinite"
    B = _laplacian(400)
    assert pcg(B, np.ones(400), lambda r: r, rtol=1e-12, maxiter=3).status == "budget"


def test_the_forcing_term_is_at_most_its_bound_and_shrinks_with_a_fast_residual():
    assert forcing(1.0, None, None) == 0.1
    assert forcing(1e-3, 1.0, 0.1) == pytest.approx(0.9e-6)
    assert forcing(1.0, 1.0, 0.1) == 0.1


def _curtain(n=12):
    cfg = scenes.config("curtain", nodes=(n, n), fabric="", mu=0.2, eta=20.0, xi=1e-4, shear=1.0)  # issue 44's
    return make_model(scenes.build(cfg), "fd"), cfg.dt


def test_the_step_test_ends_on_a_short_direction_and_stays_within_its_tolerance_of_a_tight_solve():
    model, dt = _curtain()
    steps = 20
    tight = dm.TimeStepper(model, dt, newton=dict(test="force", rtol=1e-10))
    ref = tight.run(model.initial_state(), steps=steps).state.X
    st = dm.TimeStepper(model, dt, newton=dict(test="step", vtol=1e-2))
    X = st.run(model.initial_state(), steps=steps).state.X
    reports = st.newton_reports
    by_step = [r for r in reports if r.by == "step"]
    assert by_step, "no solve ended on the step test"
    assert all(0 < r.step <= r.xtol == pytest.approx(1e-2 * dt) for r in by_step)
    # each step leaves at most its direction (<= vtol dt) unresolved: the difference stays under steps * vtol dt
    assert np.max(np.abs(X - ref)) <= steps * 1e-2 * dt


def test_a_lagged_factorisation_serves_several_steps():
    model, dt = _curtain()
    st = dm.TimeStepper(model, dt, newton=dict(test="step", lag=True))
    st.run(model.initial_state(), steps=20)
    factorisations = sum(r.factorisations for r in st.newton_reports)
    plain = dm.TimeStepper(model, dt, newton=dict(test="step", lag=False))
    plain.run(model.initial_state(), steps=20)
    assert factorisations < sum(r.factorisations for r in plain.newton_reports)


def test_a_step_far_larger_than_the_motion_does_not_make_energy():
    """The hanging cloth at dt = 5 s (its swing's period is about 2 s): the first Newton step moves the sheet
    about 100 m before it comes back. A chord of that first factorisation kept the iterate on another branch,
    where the run's energy grew from 4.4 J to 315 J (the guard's divergence); a factorisation is now renewed
    after an iteration that raised the residual or moved a node further than a grid spacing."""
    cfg = scenes.config("hanging", nodes=(8, 8))
    model = make_model(scenes.build(cfg), "fd")
    result = dm.TimeStepper(model, 5.0).run(model.initial_state(), steps=16)
    assert result.status == "finished", result.message


def test_a_run_resumed_under_a_lagged_factorisation_is_the_same_run_and_a_foreign_one_is_refused():
    """``lag=True``: the controller's memory says where the kept factorisation was made, and a stepper restored
    from it makes it again: the run goes on bit for bit as the uninterrupted one. Memories that do not fit the
    model are refused, naming the key."""
    model, dt = _curtain()
    newton = dict(lag=True)
    whole = dm.TimeStepper(model, dt, newton=newton)
    taken = {}

    def keep(state):
        if state.step == 9:
            taken["state"], taken["memory"] = state, whole.memory()

    end = whole.run(model.initial_state(), steps=24, trackers=[dm.Callback(keep)]).state
    memory = taken["memory"]
    assert "lag" in memory  # the premise: a factorisation outlived its step here
    lag = memory["lag"]
    assert len(lag["x"]) == 3 * model.ndof and lag["cm"] > 0
    again = dm.TimeStepper(model, dt, newton=newton)
    again.restore(memory)
    resumed = again.run(model.initial_state(), steps=24 - 9, resume=taken["state"]).state  # the steps left
    np.testing.assert_array_equal(resumed.X, end.X)
    np.testing.assert_array_equal(resumed.V, end.V)
    for key, value, field in (("x", [0.0] * 5, "memory.lag.x"), ("damping", [[0], [1]], "memory.lag.damping"),
                              ("cm", -1.0, "memory.lag.cm")):
        with pytest.raises(InputError, match=field):
            dm.TimeStepper(model, dt, newton=newton).restore(dict(memory, lag=dict(lag, **{key: value})))


@pytest.mark.parametrize("field, value", [("test", "residual"), ("vtol", 0.0), ("vtol", float("nan")),
                                          ("lag", 1), ("contraction", -1.0), ("chords", 0.0),
                                          ("fallback", "gauss")])
def test_bad_settings_are_refused_naming_the_field(field, value):
    with pytest.raises(InputError, match=field):
        NewtonSettings(**{field: value})


def test_a_scene_grid_is_fd_nodes_and_half_as_many_fe_elements():
    assert descriptor("fd").scene_nodes((64, 48)) == (64, 48)
    assert descriptor("fe").scene_nodes((64, 48)) == (33, 25)
    assert descriptor("fe").scene_nodes((4, 4)) == (3, 3)
