"""Self-contact in Newton's method (deformable.contact.terms): a sheet bent into a U whose two legs fly at each other
at 5 m/s each (10 m/s closing) meets itself, never crosses itself at any step, and bounces back; with a thickness,
no two primitives come closer than it; on both backends (FE under the slow marker: its impact costs 12 s)."""

import math

import numpy as np
import pytest

import deformable as dm
from deformable.contact.selfmesh import ContactMesh
from fdmodel import FDModel
from femodel import FEModel

GAP, DHAT, SPEED = 0.1, 0.01, 5.0


def u_fold(a1, a2):
    """The unit sheet bent into a U across a2 (its arc length): flat legs GAP apart joined by a half circle."""
    R = GAP / 2
    s1 = (1.0 - math.pi * R) / 2
    theta = np.clip((a2 - s1) / R, 0.0, math.pi)
    y = np.where(a2 < s1, a2, np.where(theta < math.pi, s1 + R * np.sin(theta), s1 - (a2 - s1 - math.pi * R)))
    z = np.where(a2 < s1, 0.0, R * (1 - np.cos(theta)))
    return np.stack([np.asarray(a1, float) + 0 * y, y, z], -1)


def closing(a1, a2):
    """The legs' velocity: +SPEED at z = 0, -SPEED at z = GAP, linear in z between (m/s)."""
    z = u_fold(a1, a2)[..., 2]
    return np.stack([0 * z, 0 * z, SPEED * (1 - 2 * z / GAP)], -1)


def impact(cls, nodes, thickness=0.0, t_end=0.02):
    full = np.full((2, 2), 1.0)
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(nodes, nodes), initial=u_fold),
                     dm.Material(mu=0.1, gamma=0.0, eta=10.0 * full, xi=1e-4 * full),
                     contact=dm.Contact(self_distance=DHAT, thickness=thickness), force_model="variational")
    model = cls(scene)
    mesh = ContactMesh(model, DHAT)
    stepper = dm.TimeStepper(model, 1e-3, "implicit-euler")
    states = list(stepper.iterate(model.initial_state(), V0=model.discretize(closing), t_end=t_end))
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


def test_self_contact_on_the_semi_implicit_scheme_is_refused_in_one_line():
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(6, 6)), dm.Material(mu=0.1, eta=10.0, xi=1e-4),
                     contact=dm.Contact(self_distance=DHAT))
    with pytest.raises(ValueError, match="self_distance"):
        dm.TimeStepper(FDModel(scene), 1e-3, "semi-implicit")


@pytest.mark.parametrize("field,value", [("self_distance", 0.0), ("self_distance", -1.0), ("thickness", -1e-3),
                                         ("thickness", math.inf)])
def test_contact_rejects_a_bad_self_distance_or_thickness_naming_it(field, value):
    with pytest.raises(ValueError, match=f"Contact.{field}"):
        dm.Contact(**{field: value})
