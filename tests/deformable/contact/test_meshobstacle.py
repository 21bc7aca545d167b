"""Triangle-mesh obstacles (deformable.MeshObstacle): read from a file or given as arrays, static or on a rigid path,
met by the sheet triangle against triangle (deformable.contact.meshpotential).

- the file and the arrays give one obstacle; bad input is one error naming the field;
- the rigid path (Rodrigues' rotation about the pivot, a translation);
- a scene file names a mesh beside it; the resolved config reads back equal;
- the barrier's gradient is the derivative of its energy, its Hessian symmetric positive semi-definite;
- no step of any run intersects an obstacle: a sheet falling on a pyramid whose apex lies between its nodes (where
  contact points alone would let it through), a paddle striking a hanging sheet at 5 m/s, FD and FE;
- the semi-implicit scheme (the paper's exponential force, which needs a signed distance) refuses a mesh.
"""

import dataclasses
import math

import meshio
import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from deformable.contact.meshobstacle import MeshObstacle, icosphere, rotation, sag
from deformable.contact.meshpotential import MeshObstaclePotential, ObstacleMesh
from deformable.errors import InputError
from deformable.geometry.surfaces import Plane
from deformable.solve.potential import flat, unflat
from fdmodel import FDModel
from femodel import FEModel
from validation.studies.meshcontact import box_mesh

CLOTH = dict(mu=0.2, gamma=0.1, eta=np.full((2, 2), 20.0), xi=np.full((2, 2), 1e-5))
DHAT = 1e-3


def pyramid(apex, base: float, height: float) -> MeshObstacle:
    """A square pyramid standing on z = apex z - height, its apex up: four sides and a base of two triangles."""
    a = np.asarray(apex, float)
    b = base / 2
    V = np.array([a, a + (-b, -b, -height), a + (b, -b, -height), a + (b, b, -height), a + (-b, b, -height)])
    F = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1], [1, 3, 2], [1, 4, 3]])
    return MeshObstacle(vertices=V, faces=F)


def falling_sheet(nodes, height, obstacles, size=(0.2, 0.2), force_model="variational", **contact):
    sheet = dm.Sheet(size=size, nodes=nodes, initial=Plane(origin=(0.0, 0.0, height)))
    return dm.Scene(sheet, dm.Material(**CLOTH), forces=[dm.Gravity()], force_model=force_model,
                    obstacles=obstacles, contact=dm.Contact(distance=DHAT, **contact))


# -- the obstacle -----------------------------------------------------------------------------
@pytest.mark.parametrize("suffix", [".obj", ".ply", ".vtk"])
def test_a_mesh_file_reads_back_as_the_arrays_it_was_written_from(tmp_path, suffix):
    ball = icosphere((0.1, 0.2, 0.3), 0.25, 1)
    path = tmp_path / f"ball{suffix}"
    meshio.write(path, meshio.Mesh(ball.points(), [("triangle", ball.triangles)]))
    read = MeshObstacle(path=str(path))
    assert np.max(np.abs(read.points() - ball.points())) <= 1e-6  # text formats keep 7 or more digits
    assert np.array_equal(read.triangles, ball.triangles)
    assert read.kind == "mesh" and not read.analytic and not read.moving


@pytest.mark.parametrize("kwargs,field", [
    (dict(), "MeshObstacle.path"),
    (dict(path="x.obj", vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]]), "MeshObstacle.path"),
    (dict(path="no-such-file.obj"), "MeshObstacle.path"),
    (dict(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]]), "MeshObstacle.faces"),
    (dict(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], faces=[[0, 1, 3]]), "MeshObstacle.faces"),
    (dict(vertices=[[0, 0, 0], [1, 0, 0], [2, 0, 0]], faces=[[0, 1, 2]]), "MeshObstacle.faces"),
    (dict(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5]], faces=[[0, 1, 2]]), "MeshObstacle.vertices"),
    (dict(vertices=[[0, 0, 0], [1, 0, math.nan], [0, 1, 0]], faces=[[0, 1, 2]]), "MeshObstacle.vertices"),
    (dict(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], faces=[[0, 1, 2]], velocity=(1, 2)), "MeshObstacle.velocity"),
])
def test_bad_input_is_one_error_naming_the_field(kwargs, field):
    with pytest.raises(InputError, match=field.replace(".", r"\.")) as err:
        MeshObstacle(**kwargs)
    assert err.value.field == field and "\n" not in str(err.value)


def test_a_file_without_triangles_is_refused_naming_its_cells(tmp_path):
    path = tmp_path / "lines.vtk"
    meshio.write(path, meshio.Mesh(np.eye(3), [("line", np.array([[0, 1], [1, 2]]))]))
    with pytest.raises(InputError, match="has no triangles .cells: line"):
        MeshObstacle(path=str(path))


def test_the_rigid_path_turns_about_the_pivot_and_translates():
    ball = icosphere((0.0, 0.0, 0.0), 0.1, 1)
    omega = np.array([0.0, 0.0, 2.0])  # rad/s about z through the pivot
    pivot = np.array([0.3, 0.0, 0.0])
    turning = MeshObstacle(vertices=ball.points() + (1.0, 0.0, 0.0), faces=ball.triangles, angular_velocity=omega,
                           pivot=pivot, velocity=(0.0, 0.0, 0.5))
    Y0 = turning.points(0.0)
    t = 0.7
    Y = turning.points(t)
    radial = lambda P: np.linalg.norm((P - pivot)[:, :2], axis=1)  # noqa: E731
    assert np.max(np.abs(radial(Y) - radial(Y0))) <= 1e-14  # a rotation about the vertical through the pivot
    assert np.max(np.abs(Y[:, 2] - (Y0[:, 2] + 0.5 * t))) <= 1e-14  # and the translation
    R = rotation(omega * t)
    assert np.allclose(R @ R.T, np.eye(3), rtol=0, atol=1e-15) and np.linalg.det(R) == pytest.approx(1.0, abs=1e-15)
    full = turning.points(2 * math.pi / 2.0)  # one turn: back where it started, lifted
    assert np.max(np.abs(full[:, :2] - Y0[:, :2])) <= 1e-13
    assert turning.moving and not MeshObstacle(vertices=Y0, faces=ball.triangles).moving


def test_the_triangulation_error_of_the_icosphere_falls_four_times_a_level():
    errors = [sag(icosphere((0, 0, 0), 0.25, k), (0, 0, 0), 0.25) for k in (2, 3, 4)]
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 3.6) & (ratios < 4.4)), f"sag ratios {ratios}"  # O(h^2), h halving each level


def test_a_scene_file_reads_a_mesh_beside_it_and_its_config_reads_back_equal(tmp_path):
    V, F = box_mesh((0.4, 0.4, -0.2), (0.6, 0.6, -0.01))
    meshio.write(tmp_path / "stool.obj", meshio.Mesh(V, [("triangle", F)]))
    (tmp_path / "scene.toml").write_text('scene = "floor"\n[[obstacles]]\nkind = "mesh"\npath = "stool.obj"\n'
                                         'velocity = [0.0, 0.0, 0.1]\n')
    cfg = scenes.read_toml(tmp_path / "scene.toml")
    mesh = cfg.obstacles[0]
    assert mesh.path == str(tmp_path / "stool.obj") and mesh.velocity == (0.0, 0.0, 0.1)
    assert np.allclose(mesh.points(), V, rtol=0, atol=1e-6)
    assert scenes.read_toml_text(scenes.to_toml(cfg)) == cfg
    built = scenes.build(cfg.replace(nodes=(5, 5)))
    assert [o.kind for o in built.obstacles] == ["plane", "mesh"]


def test_an_obstacle_that_crosses_itself_is_not_counted_against_the_sheet():
    """Two boxes through each other as one mesh (a scanned or assembled mesh often crosses itself): the IPC
    Toolkit's own test finds the crossing, but only sheet-obstacle pairs count, so the sheet 1 cm above it is clear
    at 1 cm."""
    import ipctk

    A, B = box_mesh((0.0, 0.0, -0.1), (0.2, 0.05, 0.0)), box_mesh((0.05, -0.05, -0.15), (0.1, 0.15, -0.05))
    V, F = np.vstack([A[0], B[0]]), np.vstack([A[1], B[1] + 8]).astype(np.int32)
    alone = ipctk.CollisionMesh(V, np.asarray(ipctk.edges(F), np.int32), F)
    assert ipctk.has_intersections(alone, np.asfortranarray(V))
    obstacle = MeshObstacle(vertices=V, faces=F)
    model = FDModel(falling_sheet((5, 5), 0.01, (obstacle,)))
    mesh = ObstacleMesh(model, (obstacle,))
    X = model.initial_state()
    assert not mesh.intersects(X)
    assert mesh.distance(X) == pytest.approx(0.01, rel=1e-9)
    assert math.isfinite(MeshObstaclePotential(model, (obstacle,), DHAT, 2.0, 1e12).energy(flat(X)))


# -- the barrier --------------------------------------------------------------------------------
def test_the_barrier_gradient_is_the_derivative_of_its_energy_and_its_hessian_is_psd():
    ball = icosphere((0.1, 0.1, -0.1), 0.1, 2)
    model = FDModel(falling_sheet((9, 9), 3e-4, (ball,)))
    pot = MeshObstaclePotential(model, (ball,), DHAT, pressure=2.0, limit=1e12)
    x = flat(model.initial_state())
    assert pot.energy(x) > 0
    rng = np.random.default_rng(3)
    dx = rng.standard_normal(x.size) * 1e-5
    dx *= pot.max_step(x, dx)  # the direction stays collision-free
    h = 1e-3
    numeric = (pot.energy(x + h * dx) - pot.energy(x - h * dx)) / (2 * h)
    g = pot.gradient(x)
    assert numeric == pytest.approx(g @ dx, rel=1e-5)
    H = pot.hessian(x).toarray()
    assert np.max(np.abs(H - H.T)) <= 1e-12 * np.max(np.abs(H))
    assert np.min(np.linalg.eigvalsh(H)) >= -1e-9 * np.max(np.abs(H))


def _run(model, t_end, dt=2e-3, V0=None):
    mesh = ObstacleMesh(model, [o for o in model.scene.obstacles if not o.analytic])
    stepper = dm.TimeStepper(model, dt, "implicit-euler")
    states = list(stepper.iterate(model.initial_state(), V0=V0, t_end=t_end))
    assert states[-1].t == pytest.approx(t_end)
    return mesh, states


def test_a_pyramid_whose_apex_lies_between_the_nodes_never_passes_the_sheet():
    """FD 5 x 5 nodes, h = 5 cm: the apex sits under the middle of a cell, where no node is; a sheet dropped on it
    from 1 cm rests on the apex, the cell's triangles held above it (contact points at the nodes would let the
    apex through the cell)."""
    apex = (0.075, 0.075, 0.0)  # the middle of the cell between nodes (1, 1) and (2, 2)
    model = FDModel(falling_sheet((5, 5), 0.01, (pyramid(apex, 0.04, 0.05),)))
    mesh, states = _run(model, 0.15)
    assert not any(mesh.intersects(s.X, s.t) for s in states)
    gaps = [mesh.distance(s.X, s.t) for s in states]
    assert min(gaps) > 0
    assert min(gaps) < DHAT  # it came to rest on the apex, within the barrier's reach
    assert _height_over(mesh, states[-1].X, apex) > apex[2]  # the sheet's surface over the apex is above it


def _height_over(mesh, X, point) -> float:
    """The height (m) of the sheet's contact mesh over (x, y) of a point: its triangle there, linearly."""
    V = mesh.points.positions(X)
    for tri in mesh.faces[:2 * (mesh.points.shape[0] - 1) * (mesh.points.shape[1] - 1)]:
        a, b, c = V[tri]
        T = np.array([b[:2] - a[:2], c[:2] - a[:2]]).T
        u, v = np.linalg.solve(T, np.asarray(point[:2]) - a[:2])
        if u >= 0 and v >= 0 and u + v <= 1:
            return float(a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]))
    raise AssertionError("no triangle of the sheet lies over the point")


def test_a_resumed_run_keeps_the_adapted_stiffness_and_is_the_same_run(one_thread):
    """The sheet on the pyramid's apex (FD 5 x 5): IPC's adaptive rule doubles the mesh barrier's kappa from step 32
    on (measured: 4 doublings by step 80). A run resumed at step 40 from the state and the controller's memory
    (which holds the adapted kappa) ends where the whole run does, bit for bit; resumed without that memory, it
    does not. Bit for bit on one IPC Toolkit thread (the fixture): on two, its parallel sums moved the end by up
    to 6.5e-16 m in one of three runs."""
    model = FDModel(falling_sheet((5, 5), 0.01, (pyramid((0.075, 0.075, 0.0), 0.04, 0.05),)))
    whole = dm.TimeStepper(model, 2e-3)
    kept = {}

    def keep(state):
        if state.step == 40:
            kept["state"], kept["memory"] = state, whole.memory()

    end = whole.run(model.initial_state(), steps=80, trackers=[dm.Callback(keep)]).state
    assert kept["memory"]["contact"]["raised"] >= 1  # the premise: kappa adapted before the resumption
    again = dm.TimeStepper(model, 2e-3)
    again.restore(kept["memory"])
    resumed = again.run(model.initial_state(), steps=40, resume=kept["state"]).state
    np.testing.assert_array_equal(resumed.X, end.X)
    forgetful = dm.TimeStepper(model, 2e-3)
    forgetful.restore({k: v for k, v in kept["memory"].items() if k != "contact"})
    assert not np.array_equal(forgetful.run(model.initial_state(), steps=40, resume=kept["state"]).state.X, end.X)
    with pytest.raises(InputError, match="memory.contact.kappa"):
        dm.TimeStepper(model, 2e-3).restore({**kept["memory"], "contact": {"kappa": -1.0}})


@pytest.mark.parametrize("cls,nodes", [(FDModel, (7, 7)), (FEModel, (5, 5))])
def test_a_paddle_striking_a_hanging_sheet_at_5_m_s_never_passes_it(cls, nodes):
    """A 20 cm sheet hanging from its top edge, a box 5 cm thick moving through its plane at 5 m/s: pushed aside,
    never crossed, at any step (FD and FE)."""
    sheet = dm.Sheet(size=(0.2, 0.2), nodes=nodes, rest=Plane(e2=(0.0, 0.0, 1.0)))
    V, F = box_mesh((0.05, -0.08, 0.05), (0.15, -0.03, 0.15))
    paddle = MeshObstacle(vertices=V, faces=F, velocity=(0.0, 5.0, 0.0))
    scene = dm.Scene(sheet, dm.Material(**CLOTH), forces=[dm.Gravity()], force_model="variational",
                     constraints=[dm.Pin("top")], obstacles=(paddle,), contact=dm.Contact(distance=DHAT))
    model = cls(scene)
    mesh, states = _run(model, 0.02, dt=1e-3)
    assert not any(mesh.intersects(s.X, s.t) for s in states)
    assert min(mesh.distance(s.X, s.t) for s in states) > 0
    ys = model.grid(states[-1].X)[..., 1]
    assert np.max(ys) > 0.05  # pushed: the paddle's front is at y = 0.07 m by t = 0.02 s, and the sheet ahead of it


@pytest.mark.parametrize("cls", [FDModel, FEModel])
def test_a_rising_plate_carries_the_sheet_resting_on_it_into_the_steps_start(cls):
    """A plate rising at 1 m/s under a sheet resting 0.5 mm above it: over a 5 ms step the plate alone would strike
    the sheet standing still; the step's start (ContactTerms.safe_start) carries the sheet up with it, so that the
    plate's and the sheet's motion together are collision-free; a pinned edge in the plate's way rejects the step."""
    from deformable.contact.terms import ContactTerms
    from deformable.errors import StepRejected

    V, F = box_mesh((-0.05, -0.05, -0.02), (0.25, 0.25, 0.0))
    plate = MeshObstacle(vertices=V, faces=F, velocity=(0.0, 0.0, 1.0))
    model = cls(falling_sheet((5, 5), 5e-4, (plate,)))
    terms = ContactTerms(model)
    x = flat(model.initial_state())
    dt = 5e-3
    terms.lag(x, dt, dt)
    still = np.zeros_like(x)
    assert terms.meshes.prescribed_step(x, still) < 1.0  # the plate alone strikes the sheet within the step
    start = terms.safe_start(x, still)
    assert terms.meshes.prescribed_step(x, start - x) >= 1.0  # with the sheet carried, the motion is clear
    z = model.grid(unflat(start, model.ndof))[..., 2]
    assert np.min(z) == pytest.approx(5e-4 + 1.0 * dt, rel=1e-9)  # carried by the plate's 5 mm
    pinned = cls(dataclasses.replace(model.scene, constraints=[dm.Pin("left")]))
    pt = ContactTerms(pinned)
    pt.lag(x, dt, dt)
    fixed = np.concatenate([a * pinned.ndof + np.asarray(f, np.int64) for a, f in enumerate(pinned.fixed_dofs())])
    with pytest.raises(StepRejected, match="would strike the sheet within this step"):
        pt.safe_start(x, still, fixed)
    assert pt.blocked == 1


def test_the_semi_implicit_scheme_refuses_a_mesh_obstacle_in_one_line():
    scene = falling_sheet((5, 5), 0.01, (pyramid((0.1, 0.1, 0.0), 0.04, 0.05),), force_model="tpbf87",
                          method="exponential")
    with pytest.raises(ValueError, match="a mesh obstacle has none: use an implicit scheme"):
        dm.TimeStepper(FDModel(scene), 1e-3, "semi-implicit")


def test_a_start_intersecting_a_mesh_obstacle_is_refused():
    from deformable.contact.clearance import require_clear

    scene = falling_sheet((5, 5), -0.01, (pyramid((0.1, 0.1, 0.0), 0.04, 0.05),))
    model = FDModel(scene)
    with pytest.raises(ValueError, match="the start: the sheet intersects a mesh obstacle at t = 0 s"):
        require_clear(model, model.initial_state(), "the start")
    assert dataclasses.replace(scene).obstacles[0].kind == "mesh"
