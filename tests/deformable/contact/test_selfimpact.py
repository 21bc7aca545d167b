"""Self-contact in Newton's method (deformable.contact.terms): a sheet bent into a U whose two legs fly at each other
at 5 m/s each (10 m/s closing) meets itself, never crosses itself at any step, and bounces back; with a thickness,
no two primitives come closer than it; on both backends (FE under the slow marker: its impact costs 12 s)."""

import math

import numpy as np
import pytest

import deformable as dm
from deformable.contact.selfmesh import ContactMesh
from deformable.errors import SelfContactIgnored
from fdmodel import FDModel
from femodel import FEModel
from validation.harness.folds import DHAT, GAP, closing, impact_scene


def impact(cls, nodes, thickness=0.0, t_end=0.02):
    model = cls(impact_scene(nodes, thickness))
    mesh = ContactMesh(model, DHAT)
    stepper = dm.TimeStepper(model, 1e-3, "implicit-euler")
    states = list(stepper.iterate(model.initial_state(), V0=model.discretize(closing()), t_end=t_end))
    return model, mesh, states


def _check(model, mesh, states, thickness):
    crossed = [s.t for s in states if mesh.intersects(s.X)]
    assert crossed == []
    distances = np.array([mesh.self_distance(s.X, 3 * DHAT) for s in states])
    assert np.min(distances) < DHAT  # the legs met: within the barrier's reach
    assert np.min(distances) > thickness
    # and bounced: the legs move apart at the end (the lower leg's mean vertical velocity downwards)
    X0 = model.initial_state()
    lower = np.asarray(model.value_dofs)[X0[np.asarray(model.value_dofs), 2] < 1e-12]
    assert np.mean(states[-1].V[lower, 2]) < 0


def test_fd_legs_meeting_at_5_m_s_never_cross_and_bounce_back():
    model, mesh, states = impact(FDModel, 16)
    _check(model, mesh, states, 0.0)


def test_fd_legs_meeting_at_5_m_s_stay_a_thickness_apart():
    thickness = 2e-3
    model, mesh, states = impact(FDModel, 16, thickness)
    _check(model, mesh, states, thickness)


@pytest.mark.slow
def test_fe_legs_meeting_at_5_m_s_never_cross_and_bounce_back():
    model, mesh, states = impact(FEModel, 9)
    _check(model, mesh, states, 0.0)


def test_self_contact_on_the_semi_implicit_scheme_is_left_out_with_a_warning():
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(6, 6)), dm.Material(mu=0.1, eta=10.0, xi=1e-4),
                     contact=dm.Contact(self_distance=DHAT))
    with pytest.warns(SelfContactIgnored, match="self_distance"):
        dm.TimeStepper(FDModel(scene), 1e-3, "semi-implicit")


@pytest.mark.parametrize("field,value", [("self_distance", -1.0), ("self_distance", math.nan), ("thickness", -1e-3),
                                         ("thickness", math.inf)])
def test_contact_rejects_a_bad_self_distance_or_thickness_naming_it(field, value):
    with pytest.raises(ValueError, match=f"Contact.{field}"):
        dm.Contact(**{field: value})


def test_a_self_distance_of_zero_turns_self_contact_off():
    assert dm.Contact(self_distance=0.0).self_distance is None


def test_the_curtain_has_self_contact_under_the_variational_model_only():
    from deformable import scenes

    assert scenes.build(scenes.config("curtain", nodes=(6, 6))).contact.self_distance == 4e-3
    assert scenes.build(scenes.config("curtain", nodes=(6, 6), force_model="tpbf87")).contact is None
    off = scenes.config("curtain", nodes=(6, 6)).replace(contact={"self_distance": 0.0})
    assert scenes.build(off).contact.self_distance is None


def test_a_prescribed_motion_through_the_sheet_pushes_it_along_or_rejects_the_step_and_a_free_one_starts_clear():
    """The top leg's nodes held and prescribed to move down through the lower leg: the step's start carries the free
    lower leg in its way along with it (the start clear of itself, the held nodes at their targets); with the lower
    leg held too, nothing can give way and the start refuses it (StepRejected, counted as blocked), so the stepper
    retries shorter; a prescribed motion away from the lower leg is taken whole, the free rest of the way clipped
    to keep the sheet clear of itself."""
    from deformable.contact.terms import ContactTerms
    from deformable.errors import StepRejected

    model = FDModel(impact_scene(16, 2e-3))
    terms = ContactTerms(model)
    X = model.initial_state()
    x, n = X.T.ravel(), model.ndof
    held = 2 * n + np.flatnonzero(X[:, 2] > GAP - 1e-9)  # the upper leg's z coordinates
    lower = 2 * n + np.flatnonzero(X[:, 2] < 1e-9)
    dx = np.zeros_like(x)
    dx[held] = -2 * GAP  # through the lower leg and beyond
    start = terms.safe_start(x, dx, held)
    np.testing.assert_allclose(start[held], x[held] - 2 * GAP)
    assert np.min(start[lower] - x[lower]) == pytest.approx(-2 * GAP)  # the lower leg below it pushed along
    mesh = terms.sheet.mesh
    assert not mesh.intersects(start.reshape(3, n).T) and terms.blocked == 0
    pinned = np.concatenate([held, lower])
    with pytest.raises(StepRejected, match="prescribed motion"):
        terms.safe_start(x, dx, pinned)
    assert terms.blocked == 1
    dx[held] = 0.01  # up, away
    dx[lower] = 2 * GAP  # the lower leg's own (free) motion up through the upper one
    start = terms.safe_start(x, dx, held)
    np.testing.assert_allclose(start[held], x[held] + 0.01)
    assert 0 < np.max(start[lower] - x[lower]) < 2 * GAP
    assert not mesh.intersects(start.reshape(3, n).T) and mesh.self_distance(start.reshape(3, n).T, GAP) > 2e-3
