"""Issue 48: numpy's scalars are numbers, text is not, and a shell whose stiffness overflows double precision is
an input error naming the field, not an OverflowError from inside the model."""

import numpy as np
import pytest

import deformable as dm


@pytest.mark.parametrize("make, field", [
    (lambda: dm.Koiter(E=1e300, h=1e10), "Koiter.E"),
    (lambda: dm.Orthotropic(E1=1e300, E2=1e300, G12=1e5, nu12=0.3, h=1e10), "Orthotropic.E1"),
    (lambda: dm.Koiter(E="1e6"), "Koiter.E"),
    (lambda: dm.Fabric.preset("denim").material(gamma="0.1"), "Fabric.material gamma"),
    (lambda: dm.Fabric.preset("denim").material(scale=0.0), "Fabric.material scale"),
])
def test_a_value_the_model_cannot_hold_is_one_input_error_naming_its_field(make, field):
    with pytest.raises(dm.InputError) as err:
        make()
    assert err.value.field == field and "\n" not in str(err.value)


def test_numpy_scalars_are_taken_as_the_numbers_they_are():
    shell = dm.Koiter(E=np.float32(1e6), nu=np.float64(0.3), h=np.float32(1e-3))
    assert type(shell.E) is float and shell.E == 1e6 and shell.nu == 0.3
    assert dm.Koiter(E=1e6, h=1e-3).stiffnesses == pytest.approx(shell.stiffnesses, rel=1e-6)  # float32(1e-3) to 4e-8
    fabric = dm.Fabric(density=np.int64(1), bending=1e-5, tensile=100.0, shear=np.float32(5.0))
    assert type(fabric.density) is float and type(fabric.shear) is float
    assert dm.Orthotropic(E1=np.float64(2e6), E2=1e6, G12=1e5, nu12=np.float32(0.25), h=1e-3).E1 == 2e6


def test_far_too_many_contact_samples_get_the_memory_check_every_grid_gets():
    from deformable import scenes

    with pytest.raises(dm.InputError, match="contact points .* needs about .* of memory") as err:
        dm.Simulation(scenes.config("floor", nodes=(12, 12), contact={"samples": 10**6}), "fd").run(steps=1)
    assert "\n" not in str(err.value)


def test_a_scene_config_takes_numpy_scalars_and_refuses_bools():
    from deformable import scenes

    cfg = scenes.config("hanging", eta=np.int64(5), xi=np.float32(0.5), nodes=(np.int64(6), 6))
    assert (cfg.eta, cfg.xi, cfg.nodes) == (5.0, 0.5, (6, 6)) and type(cfg.nodes[0]) is int
    for value in (True, np.bool_(True), "5"):
        with pytest.raises(dm.InputError, match="scene field eta must be a finite number"):
            scenes.config("hanging", eta=value)
