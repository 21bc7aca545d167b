"""The contact mesh for self-contact (deformable.contact.selfmesh): its triangles, what may touch, the smallest
self-distance and the intersection test, against configurations whose answers are known exactly."""

import math

import ipctk
import numpy as np
import pytest

import deformable as dm
from deformable.contact.selfmesh import ContactMesh, grid_triangles
from fdmodel import FDModel
from femodel import FEModel

N = 16  # nodes a side of the 1 m sheet: h = 1/15 m


def _model(cls, nodes=(N, N)):
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=nodes), dm.Material(mu=0.1, gamma=0.0, eta=10.0, xi=1e-4),
                     force_model="variational")
    return cls(scene)


@pytest.mark.parametrize("shape", [(2, 2), (3, 5), (16, 16)])
def test_two_counter_clockwise_triangles_a_cell_and_every_edge_once(shape):
    m, n = shape
    faces = grid_triangles(shape)
    assert faces.shape == (2 * (m - 1) * (n - 1), 3)
    i, j = np.divmod(faces, n)
    area2 = (i[:, 1] - i[:, 0]) * (j[:, 2] - j[:, 0]) - (j[:, 1] - j[:, 0]) * (i[:, 2] - i[:, 0])
    assert np.all(area2 == 1), "each triangle is half a cell, counter-clockwise in (a1, a2)"
    edges = {tuple(sorted(e)) for f in faces for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    assert len(edges) == (m - 1) * n + m * (n - 1) + (m - 1) * (n - 1)
    with pytest.raises(ValueError, match="2 x 2"):
        grid_triangles((1, 4))


@pytest.mark.parametrize("cls, per_side", [(FDModel, N), (FEModel, None)])
def test_a_flat_sheet_neither_crosses_nor_comes_near_itself(cls, per_side):
    model = _model(cls)
    mesh = ContactMesh(model, distance=0.02)
    m, n = mesh.points.shape
    assert per_side is None or (m, n) == (per_side, per_side)
    assert len(mesh.faces) == 2 * (m - 1) * (n - 1) and mesh.excluded == frozenset()
    X = model.initial_state()
    assert not mesh.intersects(X) and mesh.self_distance(X) == math.inf


def _folded(gap: float, crossing: bool = False) -> np.ndarray:
    """FD nodes (N N, 3) of the sheet folded in half across a2 = 1/2: rows n < N/2 at z = 0, the rows beyond laid
    back over them at height ``gap`` (``crossing``: the upper half tilted through the lower one)."""
    h = 1.0 / (N - 1)
    a1, n = np.meshgrid(np.arange(N) * h, np.arange(N), indexing="ij")
    upper = n >= N // 2
    y = np.where(upper, (N - 1 - n) * h, n * h)
    z = np.where(upper, gap, 0.0)
    if crossing:  # the upper half from +gap at the crease to -gap at its free edge
        z = np.where(upper, gap * (1 - 2 * (n - N // 2) / (N - 1 - N // 2)), 0.0)
    return np.stack([a1, y, z], -1).reshape(-1, 3)


@pytest.mark.parametrize("gap", [0.005, 0.02])
def test_a_sheet_folded_over_itself_is_at_most_its_gap_from_itself_and_scales_with_it(gap):
    model = _model(FDModel)
    mesh = ContactMesh(model, distance=0.03)  # below the spacing 1/15 m: no neighbour is excluded
    X = _folded(gap)
    d = mesh.self_distance(X)
    assert not mesh.intersects(X)
    assert 0 < d <= gap * (1 + 1e-12)  # the two halves are gap apart; the crease's wall may come closer
    assert mesh.self_distance(X, within=d / 2) == math.inf  # nothing closer than the smallest distance
    assert mesh.self_distance(3 * X, within=0.09) == pytest.approx(3 * d, rel=1e-12)  # distances are lengths


def test_a_fold_pushed_through_the_sheet_is_an_intersection():
    model = _model(FDModel)
    mesh = ContactMesh(model, distance=0.03)
    assert mesh.intersects(_folded(0.02, crossing=True)) and not mesh.intersects(_folded(0.02))


def test_neighbours_closer_than_the_distance_at_rest_never_count():
    model = _model(FDModel)
    h = 1.0 / (N - 1)
    X = model.initial_state()
    # at rest a vertex is h / sqrt(2) from the far triangle of the cell beside it (across that cell's diagonal)
    fine = ContactMesh(model, distance=0.5 * h)
    assert fine.excluded == frozenset()
    assert fine.self_distance(X, within=1.2 * h) == pytest.approx(h / math.sqrt(2), rel=1e-12)
    coarse = ContactMesh(model, distance=1.2 * h)  # those pairs are within 1.2 h at rest: neighbours, excluded
    assert coarse.excluded and coarse.self_distance(X) == math.inf
    with pytest.raises(ValueError, match="distance"):
        ContactMesh(model, distance=0.0)


def test_the_monitor_records_the_smallest_self_distance_of_a_run():
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(8, 8)), dm.Material(mu=0.1, gamma=0.0, eta=10.0, xi=1e-4),
                     forces=[dm.Gravity()], constraints=[dm.Pin(["top-left", "top-right"])], force_model="variational")
    model = FDModel(scene)
    monitor = dm.SelfContactMonitor(distance=0.05, every=2)
    dm.TimeStepper(model, dt=0.01).run(model.initial_state(), t_end=0.1, trackers=[monitor])
    assert len(monitor.times) == len(monitor.distances) >= 6 and monitor.times[0] == 0.0
    assert monitor.crossed == [] and monitor.smallest == math.inf  # a sheet swinging down does not fold


def test_the_distances_at_once_are_the_ipc_toolkits_one_by_one(rng):
    """point_triangle_distances and segment_distances against the IPC Toolkit's scalar distances, on random
    primitives and on degenerate ones (a segment of no length, parallel segments, points in every Voronoi region)."""
    from deformable.contact.selfmesh import point_triangle_distances, segment_distances

    P = rng.normal(size=(600, 12))
    P[:40, 9:] = P[:40, 6:9]  # a segment of no length
    P[40:80, 6:9], P[40:80, 9:] = P[40:80, :3] + 0.3, P[40:80, 3:6] + 0.3  # parallel segments
    pt = point_triangle_distances(P[:, :3], P[:, 3:6], P[:, 6:9], P[:, 9:])
    ee = segment_distances(P[:, :3], P[:, 3:6], P[:, 6:9], P[:, 9:])
    for k in range(len(P)):
        a, b, c, d = P[k, :3], P[k, 3:6], P[k, 6:9], P[k, 9:]
        assert pt[k] == pytest.approx(math.sqrt(ipctk.point_triangle_distance(a, b, c, d)), rel=0, abs=1e-12)
        # a segment of no length: the distance to a point (the toolkit's edge-edge distance assumes two edges)
        ref = ipctk.point_edge_distance(c, a, b) if k < 40 else ipctk.edge_edge_distance(a, b, c, d)
        assert ee[k] == pytest.approx(math.sqrt(ref), rel=0, abs=1e-12)


def test_the_pairs_close_at_rest_are_those_a_pair_by_pair_search_finds():
    """The excluded vertex pairs, found with the distances at once, are those of the IPC Toolkit's candidates measured
    one by one (the former way), on a grid whose spacing is below the reach (thousands of pairs)."""
    model = FDModel(dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(24, 24)), dm.Material(), force_model="variational"))
    mesh = ContactMesh(model, distance=0.05, thickness=1e-3)
    plain = ipctk.CollisionMesh(mesh.rest, mesh.edges, mesh.faces)  # no filter yet
    candidates = ipctk.Candidates()
    candidates.build(plain, mesh.rest, 0.051)
    pairs = set()
    for kind in (candidates.fv_candidates, candidates.ee_candidates):
        for c in kind:
            if math.sqrt(max(0.0, float(c.compute_distance(mesh.rest, mesh.edges, mesh.faces)))) < 0.051:
                ids = [int(v) for v in c.vertex_ids(mesh.edges, mesh.faces)]
                pairs.update((min(u, v), max(u, v)) for u in ids for v in ids if u != v)
    assert len(pairs) > 1000 and mesh.excluded == frozenset(pairs)
