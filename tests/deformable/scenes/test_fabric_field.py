"""A scene in a named fabric (the config field ``fabric``): its density and full warp and weft weights."""

import numpy as np
import pytest

import deformable as dm
from deformable import scenes
from validation.commands import main


def test_a_fabric_sets_the_density_and_the_warp_and_weft_weights():
    cfg = scenes.config("curtain", fabric="denim")
    fabric = dm.Fabric.preset("denim")
    eta, xi = fabric.weights("variational")
    material = cfg.material()
    assert cfg.mu == material.mu == fabric.density
    np.testing.assert_array_equal(material.eta, eta)
    np.testing.assert_array_equal(material.xi, xi)
    assert eta[0, 0] != eta[1, 1] and (cfg.eta, cfg.xi) == (eta[0, 0], xi[0, 0])  # the fields show the warp's
    tpbf = scenes.config("curtain", fabric="denim", force_model="tpbf87").material()
    np.testing.assert_allclose(tpbf.eta, fabric.weights("tpbf87")[0])  # the same stiffness under the paper's force
    assert scenes.config("curtain", fabric="denim", scale=20).material().mu == pytest.approx(20 * fabric.density)


def test_a_fabric_and_its_fields_together_unknown_names_and_dropping_it():
    with pytest.raises(dm.InputError, match="fabric sets mu, eta, xi and shear") as err:
        scenes.config("curtain", fabric="denim", eta=3.0)
    assert err.value.field == "eta"
    with pytest.raises(dm.InputError, match="not a preset; known: blanket"):
        scenes.config("curtain", fabric="silk")
    with pytest.raises(dm.InputError, match="alpha and beta"):
        scenes.config("curtain", fabric="denim", force_model="frozen", alpha=1.0)
    dropped = scenes.config("curtain", fabric="denim").replace(fabric="", eta=5.0)
    assert dropped.fabric == "" and dropped.eta == 5.0 and dropped.material().eta[1, 1] == 5.0


def test_a_scene_file_and_the_command_line_take_a_fabric(tmp_path, capsys):
    cfg = scenes.read_toml_text('scene = "hanging"\nfabric = "tshirt-knit"\nnodes = [6, 6]\n')
    assert cfg.fabric == "tshirt-knit" and cfg.mu == dm.Fabric.preset("tshirt-knit").density
    assert main(["params", "curtain", "fabric=denim"]) == 0
    out = capsys.readouterr().out
    c_warp = dm.Fabric.preset("denim").bending_length[0]
    assert "fabric 'denim'" in out and f"bending length (D / (mu g))^(1/3) = {c_warp:.3g} m" in out
    assert main(["run", "hanging", "fabric=denim", "--grid", "6x6", "--steps", "2", "--out", str(tmp_path)]) == 0


def test_a_config_in_a_fabric_is_written_and_read_back_equal():
    cfg = scenes.config("curtain", fabric="denim", nodes=(16, 16))
    assert scenes.read_toml_text(scenes.to_toml(cfg)) == cfg
