"""The run controller (deformable.dynamics.stepper): schemes, arguments, divergence and resumption."""

import math

import numpy as np
import pytest

import deformable as dm
from deformable.solve.newton import NewtonSettings

from ...conftest import flat_model


def hanging(dt, nodes=25):
    """docs/design.md's measured case: 24 x 24 cells, eta = 50, mu = 0.1, h = 1/24, the top edge pinned; the
    lagged alpha makes the step conditionally stable, dt below the model's stable_step() (1.3e-3)."""
    model = flat_model("fd", nodes=(nodes, nodes), material=dm.Material(mu=0.1, gamma=0.0, eta=50.0),
                       forces=[dm.Gravity(direction=(0, -1, 0))], constraints=[dm.Pin("top")])
    return model, dm.TimeStepper(model, dt=dt)


@pytest.mark.parametrize("dt", [0.0, -1e-3, math.nan, math.inf, "fast"])
def test_stepper_rejects_non_positive_dt(dt):
    with pytest.raises(ValueError, match=r"dt must be a?\s?positive"):
        dm.TimeStepper(flat_model("fd", nodes=(5, 5)), dt=dt)


def test_each_force_model_gets_its_scheme_and_refuses_the_others():
    frozen = flat_model("fd", nodes=(5, 5), force_model="frozen", material=dm.Material(alpha=1.0))
    variational = flat_model("fd", nodes=(5, 5), force_model="variational")
    tpbf87 = flat_model("fd", nodes=(5, 5))
    assert dm.TimeStepper(tpbf87, 1e-3).scheme == dm.TimeStepper(frozen, 1e-3).scheme == "semi-implicit"
    assert dm.TimeStepper(variational, 1e-3).scheme == "implicit-euler"
    assert dm.TimeStepper(frozen, 1e-3, scheme="newmark").scheme == "newmark"
    with pytest.raises(ValueError, match="needs an energy"):
        dm.TimeStepper(tpbf87, dt=1e-3, scheme="newmark")
    with pytest.raises(ValueError, match="no strength matrix|does not have"):
        dm.TimeStepper(variational, dt=1e-3, scheme="semi-implicit")
    with pytest.raises(ValueError, match=r"scheme must be one of.*'leapfrog'"):
        dm.TimeStepper(tpbf87, dt=1e-3, scheme="leapfrog")
    assert dm.SCHEMES == ("semi-implicit", "implicit-euler", "newmark")


def test_the_old_scheme_name_warns_and_is_the_semi_implicit_scheme_bit_for_bit():
    model, new = hanging(1e-3, nodes=9)
    with pytest.warns(DeprecationWarning, match="'tpbf87' is now called 'semi-implicit'"):
        old = dm.TimeStepper(model, dt=1e-3, scheme="tpbf87")
    assert old.scheme == "semi-implicit"
    a = old.run(model.initial_state(), steps=50).state
    b = new.run(model.initial_state(), steps=50).state
    np.testing.assert_array_equal(a.X, b.X)
    np.testing.assert_array_equal(a.V, b.V)


def test_diverging_run_stops_and_returns_the_last_good_state():
    model, stepper = hanging(dt=3e-3)
    result = stepper.run(model.initial_state(), steps=400)
    assert result.status == "diverged" and "diverged at step" in result.message
    assert result.steps < 400
    assert np.all(np.isfinite(result.state.X))
    assert result.state.step == result.steps


def test_stable_step_below_the_stretching_bound_runs_to_the_end():
    model, stepper = hanging(dt=1e-3)
    result = stepper.run(model.initial_state(), steps=150, trackers=[dm.EnergyMonitor(every=50)])
    assert result.status == "finished" and result.steps == 150
    assert result.message == f"150 steps to t = {result.state.t:.6g} s"
    history = result.trackers[1].history
    assert history.shape == (4, 4) and np.all(np.isfinite(history))
    assert set(stepper.timings) == {"assembly", "factorisation", "solve"} and stepper.newton_reports == []


def test_a_resumed_run_is_bit_identical():
    model, stepper = hanging(dt=1e-3, nodes=9)
    X0 = model.initial_state()
    whole = stepper.run(X0, steps=20).state
    half = dm.TimeStepper(model, dt=1e-3).run(X0, steps=10).state
    rest = dm.TimeStepper(model, dt=1e-3).run(X0, steps=10, resume=half).state
    assert rest.step == 20 and rest.t == whole.t
    np.testing.assert_array_equal(rest.X, whole.X)
    np.testing.assert_array_equal(rest.V, whole.V)
    by_time = dm.TimeStepper(model, dt=1e-3).run(X0, t_end=0.02)
    assert by_time.steps == 20


def test_run_arguments_are_checked():
    model, stepper = hanging(dt=1e-3, nodes=5)
    X0 = model.initial_state()
    with pytest.raises(ValueError, match="exactly one of t_end and steps"):
        stepper.run(X0, steps=3, t_end=1.0)
    with pytest.raises(ValueError, match="exactly one of t_end and steps"):
        stepper.run(X0)
    with pytest.raises(ValueError, match="steps must be a non-negative integer"):
        stepper.run(X0, steps=2.5)
    with pytest.raises(ValueError, match="t_end must be later than the start time"):
        stepper.run(X0, t_end=0.0)
    with pytest.raises(ValueError, match=r"X0 has shape \(3, 3\), expected \(25, 3\)"):
        stepper.run(X0[:3], steps=1)
    with pytest.raises(ValueError, match=r"V0 has shape"):
        stepper.run(X0, V0=np.zeros(3), steps=1)


# -- the step size: "auto", retries, the floor --------------------------------------------
def test_auto_dt_of_the_semi_implicit_scheme_is_half_the_backends_stable_step():
    for backend in ("fd", "fe"):
        model = flat_model(backend, nodes=(9, 9), material=dm.Material(mu=0.1, eta=50.0))
        stepper = dm.TimeStepper(model, dt="auto")
        assert stepper.scheme == "semi-implicit"
        assert 0.45 * model.stable_step() <= stepper.dt <= 0.5 * model.stable_step()
    frozen = flat_model("fd", nodes=(5, 5), force_model="frozen", material=dm.Material(alpha=1.0))
    with pytest.raises(ValueError, match="no stretching bound; give dt"):
        dm.TimeStepper(frozen, dt="auto")


def curling(backend="fd", nodes=(9, 3), **newton):
    """A soft clamped strip with rest curvature, released from flat: far from its rest state (an arc)."""
    model = flat_model(backend, nodes=nodes, size=(1.0, 0.2), force_model="variational",
                       material=dm.Material(mu=1.0, gamma=0.5, eta=np.full((2, 2), 10.0), xi=np.full((2, 2), 1.0)),
                       constraints=[dm.Clamp("left")], rest_curvature=np.diag([3.0, 0.0]))
    return model


def test_a_step_too_large_for_newton_is_retried_with_smaller_steps_that_grow_back():
    """At dt = 1 s and two Newton iterations a step, the curling strip's first steps fail: they are retried
    with half the step; every returned step met its tolerance; dt grows back once steps converge."""
    model = curling()
    stepper = dm.TimeStepper(model, dt=1.0, newton=dict(max_iter=2))
    result = stepper.run(model.initial_state(), t_end=4.0)
    assert result.status == "finished" and result.state.t == pytest.approx(4.0, abs=1e-12)
    assert stepper.rejected > 0 and all(r.converged for r in stepper.newton_reports)
    assert len(stepper.newton_reports) == result.steps
    assert stepper.dt_now > stepper.dt_min  # grew back after the rejections
    # the test every report met: the force test's max(rtol * scale, atol) (scale: the residual at the inertial
    # predictor), raised to the round-off floor at most, or the step test's last direction within vtol * dt
    settings = NewtonSettings()
    for r, dt in zip(stepper.newton_reports, stepper.steps_taken):
        assert r.tolerance <= max(settings.rtol * r.scale, 1e-12, r.floor) and r.scale > 0
        if r.by == "step":
            assert r.step <= r.xtol == pytest.approx(settings.vtol * dt, rel=1e-12)
        else:
            assert r.by == "force" and r.residuals[-1] <= r.tolerance
    assert any(r.by == "step" for r in stepper.newton_reports)  # the default test, without obstacles


def test_a_run_whose_steps_never_converge_stalls_with_its_last_good_state():
    """max_iter = 0: no step can be taken; dt halves down to dt_min and the run stops, status "stalled"."""
    model = curling()
    X0 = model.initial_state()
    stepper = dm.TimeStepper(model, dt=0.1, newton=dict(max_iter=0))
    result = stepper.run(X0, t_end=1.0)
    assert result.status == "stalled" and result.steps == 0 and result.state.t == 0.0
    np.testing.assert_array_equal(result.state.X, X0)
    assert "dt_min = 9.77e-05 s" in result.message and stepper.rejected == 11  # 0.1 / 2^10, after 11 halvings
    with pytest.raises(dm.StalledError):
        list(stepper.iterate(X0, 1))


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_results_do_not_depend_on_the_solver_or_the_ordering_beyond_the_tolerance(backend):
    """The same implicit run with every solver at hand in double precision, and SuperLU with the COLAMD ordering
    instead of the symmetric one: the final states agree to round-off; PARDISO's single-precision factorisations
    (its default in time steps) to the step test's tolerance, vtol dt a step."""
    from deformable.algebra import solvers as linalg

    model = curling(backend, nodes=(7, 3))
    X0 = model.initial_state()
    finals = {}
    for solver in linalg.available():
        stepper = dm.TimeStepper(model, dt=0.05, newton=dict(solver=solver, rtol=1e-10, precision="double"))
        finals[solver] = stepper.run(X0, t_end=0.5).state.X
    original = linalg.SPLU_OPTIONS
    try:
        linalg.SPLU_OPTIONS = dict(original, permc_spec="COLAMD")
        stepper = dm.TimeStepper(model, dt=0.05, newton=dict(solver="superlu", rtol=1e-10))
        finals["colamd"] = stepper.run(X0, t_end=0.5).state.X
    finally:
        linalg.SPLU_OPTIONS = original
    reference = finals["superlu"]
    motion = np.max(np.abs(reference - X0))
    assert motion > 0.05
    for name, X in finals.items():
        assert np.max(np.abs(X - reference)) <= 1e-8 * motion, name
    if "pardiso" in linalg.available():
        # on the same time steps (at dt = 0.05 s FE's double precision halves one step and single precision does
        # not: the paths part by 0.4 m, both within tolerance of their own steps)
        runs = {}
        for precision in ("double", "single"):
            stepper = dm.TimeStepper(model, dt=0.025, newton=dict(solver="pardiso", rtol=1e-10, precision=precision))
            assert stepper.newton.solver.single == (precision == "single")
            runs[precision] = stepper.run(X0, t_end=0.5).state.X
            assert stepper.rejected == 0 and len(stepper.steps_taken) == 20
        assert np.max(np.abs(runs["single"] - runs["double"])) <= 20 * 1e-2 * 0.025  # 20 steps of vtol dt each
