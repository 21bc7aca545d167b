"""Helpers of the femodel tests: a model factory, the order fit, Gauss points."""

import numpy as np
import pytest

import deformable as dm
from femodel import FEModel


def fe_model(nodes=(9, 9), size=(1.0, 1.0), **scene):
    """An FE model of a sheet (flat by default); keyword arguments go to Scene."""
    material = scene.pop("material", dm.Material(mu=1.0, gamma=0.0, eta=10.0, xi=0.0))
    sheet = scene.pop("sheet", dm.Sheet(size=size, nodes=nodes))
    return FEModel(dm.Scene(sheet, material, **scene))


def observed_order(h, e) -> float:
    """Least-squares slope of log e against log h over all levels."""
    return float(np.polyfit(np.log(h), np.log(e), 1)[0])


def gauss_points(model, k: int) -> np.ndarray:
    """The k x k Gauss points of every element, (E k^2, 2) parameter coordinates."""
    x, _ = np.polynomial.legendre.leggauss(k)
    x = (x + 1) / 2
    i, j = (v.ravel()[:, None] for v in np.meshgrid(np.arange(model.M - 1), np.arange(model.N - 1), indexing="ij"))
    a1 = (i + np.repeat(x, k)) * model.h1
    a2 = (j + np.tile(x, k)) * model.h2
    return np.stack([a1.ravel(), a2.ravel()], axis=1)


@pytest.fixture
def rng():
    return np.random.default_rng(20240607)
