"""Trackers (deformable.dynamics.trackers): cadence, the energy monitor, the divergence guard, callbacks."""

import numpy as np

import deformable as dm

from ...conftest import flat_model


def falling(nodes=9):
    model = flat_model("fd", nodes=(nodes, nodes), material=dm.Material(mu=0.1, gamma=0.0, eta=50.0),
                       forces=[dm.Gravity(direction=(0, -1, 0))], constraints=[dm.Pin("top")])
    return model, dm.TimeStepper(model, dt=2e-3)


def test_energy_monitor_records_at_its_cadence_and_at_the_end():
    model, stepper = falling()
    monitor = dm.EnergyMonitor(every=4)
    result = stepper.run(model.initial_state(), steps=10, trackers=[monitor])
    h = monitor.history
    np.testing.assert_allclose(h[:, 0], [0.0, 0.008, 0.016, 0.020])
    e = model.energy(result.state.X)
    assert h[-1, 1:].tolist() == [e.stretching, e.bending, model.kinetic_energy(result.state.V)]
    assert h[0, 1:].sum() == 0 and np.all(h[1:, 3] > 0)  # starts at rest, then falls


def test_energy_bound_of_the_guard_stops_the_run():
    model, stepper = falling(nodes=25)
    guard = dm.DivergenceGuard(max_energy=1e-6)
    result = stepper.run(model.initial_state(), steps=100, trackers=[guard])
    assert result.status == "diverged" and "energy" in result.message
    assert model.energy(result.state.X).total <= 1e-6


def test_displacement_and_stretch_bounds_of_the_guard():
    model, stepper = falling()
    result = stepper.run(model.initial_state(), steps=100, trackers=[dm.DivergenceGuard(max_displacement=1e-3)])
    assert result.status == "diverged" and "displacement" in result.message
    assert np.max(np.abs(result.state.X - model.initial_state())) <= 1e-3
    result = stepper.run(model.initial_state(), steps=100, trackers=[dm.DivergenceGuard(max_stretch=1.0 + 1e-4)])
    assert result.status == "diverged" and "stretched" in result.message


def test_a_callback_that_returns_a_reason_stops_the_run_at_that_state():
    model, stepper = falling()
    seen = []

    def watch(state):
        seen.append(state.step)
        return "enough" if state.step == 6 else None

    result = stepper.run(model.initial_state(), steps=100, trackers=[dm.Callback(watch, every=3),
                                                                     dm.ProgressBar(disable=True)])
    assert result.status == "stopped" and result.message == "enough"
    assert seen == [3, 6] and result.state.step == 6
