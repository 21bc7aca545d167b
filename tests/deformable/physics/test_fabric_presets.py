"""The named fabrics (deformable.physics.fabric_presets, Fabric.preset): their values derived from their sources'.

The derived values below are those of the sources' table (what public sources state about named fabrics, its
rows "derived" for the ARCSim files of Wang, O'Brien, Ramamoorthi 2011, at RJshra/arcsim@dde012f6): T along
u = 2 c11, along v = 2 c22 (ARCSim's code), S = c33 / 2, and Peirce's bending length at 0 and 90 degrees; the
presets derive them in code from the file values, so a wrong factor in T, S or D, or warp and weft swapped,
fails here."""

import math

import numpy as np
import pytest

from deformable.errors import InputError
from deformable.physics import fabric_presets as fp
from deformable.physics.fabric import Fabric, G

#: preset -> (T along u, T along v (N/m), S (N/m), c at 0 deg, c at 90 deg (m)): fabrics.csv's derived rows
DERIVED = {
    "denim": (410.704, 2027.77, 26.6936, 0.0272363, 0.0312485),
    "cotton-poly": (4033.11, 4069.95, 52.3798, 0.0387373, 0.0387373),
    "tablecloth": (4004.17, 4054.97, 9.59451, 0.0345376, 0.0292096),
    "jacket-polyester": (86.1353, 342.85, 7.15735, 0.0234522, 0.026381),
    "blanket": (303.008, 489.661, 15.1251, 0.0374108, 0.029901),
    "tshirt-knit": (33.1877, 68.9542, 18.4302, 0.0232983, 0.0198151),
    "jacket-knit": (62.2924, 88.0573, 15.9482, 0.0235441, 0.0237175),
    "rib-knit": (85.742, 130.332, 41.5878, 0.0257546, 0.0228388),
    "sweater": (24.9727, 6.54487, 8.80814, 0.0300268, 0.0274881),
    "swimsuit": (95.9424, 209.231, 30.3868, 0.0311105, 0.0294347),
}
#: paper.json (the authors' estimate): fabrics.csv's Peirce bending length, derived
PAPER_C = 0.0741617


def test_there_are_at_least_six_presets_sorted_and_short():
    names = Fabric.presets()
    assert len(names) >= 6 and names == tuple(sorted(names)) == fp.names()
    assert set(DERIVED) | {"paper"} == set(names)
    assert all(n == n.lower() and " " not in n and len(n) <= 20 for n in names)


@pytest.mark.parametrize("name", fp.names())
def test_every_value_is_finite_and_positive_and_cited(name):
    f = Fabric.preset(name)
    values = [f.density, *f.tensile, *f.bending, *f.bending_length] + ([f.shear] if f.shear is not None else [])
    assert all(math.isfinite(v) and v > 0 for v in values)
    eta, xi = f.weights()
    assert np.all(np.isfinite(eta)) and np.all(eta > 0) and np.all(np.isfinite(xi)) and np.all(xi > 0)
    assert "RJshra/arcsim@dde012f6fac093701f374255eedb6d619ed926c4" in f.source and f.name
    if name == "paper":
        assert "estimate, not a measurement" in f.name and "not a measurement" in f.source
    else:
        assert "Wang, O'Brien, Ramamoorthi 2011" in f.source


@pytest.mark.parametrize("name", sorted(DERIVED))
def test_tensile_is_twice_the_file_value_and_shear_half_c33(name):
    """ARCSim's code reading: T = 2 c11 along u = warp, 2 c22 along v = weft; S = c33 / 2."""
    f, m = Fabric.preset(name), fp.lookup(name)
    assert fp.STRETCH_FACTOR == 2.0 and fp.SHEAR_FACTOR == 0.5
    assert f.tensile == pytest.approx((2 * m.stretching[0], 2 * m.stretching[1]), rel=1e-15)
    assert f.shear == pytest.approx(m.shear / 2, rel=1e-15)
    Tu, Tv, S, _, _ = DERIVED[name]
    assert f.tensile == pytest.approx((Tu, Tv), rel=1e-5)  # the table's six digits
    assert f.shear == pytest.approx(S, rel=1e-5)


def test_paper_takes_the_same_reading_and_the_default_shear():
    f = Fabric.preset("paper")
    assert f.tensile == (1e6, 1e6) and f.shear is None  # 2 x the file's 'Eh' = 0.5 MN/m
    assert f.weights()[0][0, 1] == pytest.approx(1e6 / 2 / 4)  # Fabric's default S = mean T / 2, eta_12 = S / 4
    assert f.bending_length == pytest.approx((PAPER_C, PAPER_C), rel=1e-5)


@pytest.mark.parametrize("name", sorted(DERIVED))
def test_bending_lengths_are_the_sources_warp_across_the_hinge(name):
    """c_warp is the 90-degree row's (hinge across u), c_weft the 0-degree row's, as the table derives them."""
    f, m = Fabric.preset(name), fp.lookup(name)
    *_, c0, c90 = DERIVED[name]
    assert f.bending_length == pytest.approx((c90, c0), rel=1e-5)
    assert f.bending == (m.bending[2], m.bending[0])
    assert f.weights()[1][0, 0] == pytest.approx(m.bending[2] / 2, rel=1e-15)  # xi_11 = D_warp / 2
    assert f.bending_length[0] == pytest.approx((m.bending[2] / (m.density * G)) ** (1 / 3), rel=1e-15)


def test_an_unknown_name_is_one_line_naming_the_field_and_the_presets():
    with pytest.raises(InputError) as err:
        Fabric.preset("silk")
    text = str(err.value)
    assert len(text.splitlines()) == 1 and text.startswith("fabric 'silk'") and err.value.field == "fabric"
    assert all(n in text for n in Fabric.presets())
    with pytest.raises(InputError, match="fabric"):
        Fabric.preset(None)


def test_the_docstring_table_is_the_presets():
    lines = {ln.split()[0]: ln for ln in fp.__doc__.splitlines() if ln.split() and ln.split()[0] in fp.SOURCES}
    assert set(lines) == set(fp.names())
    for name, line in lines.items():
        f = Fabric.preset(name)
        cells = line.split()
        assert float(cells[1]) == pytest.approx(1e3 * f.density)
        assert [float(cells[k]) for k in (2, 4)] == pytest.approx(f.tensile, rel=5e-3)
        assert [float(cells[k]) for k in (5, 7)] == pytest.approx([1e6 * d for d in f.bending], rel=5e-3)
        assert [float(cells[k]) for k in (8, 10)] == pytest.approx([100 * c for c in f.bending_length], abs=5e-3)


