"""validation.harness.drape: the shadow's area against a patch of known area."""

import numpy as np

from validation.harness.drape import raster_area, shadow_area


def test_the_extrapolated_shadow_area_removes_the_fills_first_order_bias():
    m, n = 30, 200
    r = np.linspace(0.0, 1.0, m)[:, None]
    t = np.linspace(0.0, 2 * np.pi, n)[None, :]
    R = 0.15 * (1 + 0.2 * np.cos(4 * t))
    P = np.stack([R * r * np.cos(t), R * r * np.sin(t), 0 * r * t], axis=-1)
    x, y = P[-1, :, 0], P[-1, :, 1]
    exact = 0.5 * abs(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))  # the boundary polygon's area
    raw = raster_area(P, pixels=4096) / exact - 1
    assert 1e-4 < raw < 1e-3  # counts every pixel the boundary touches
    assert abs(shadow_area(P, pixels=4096) / exact - 1) < 0.1 * raw
