"""Checkpoints (deformable.io.checkpoint): what is stored, read back, and refused."""

import numpy as np
import pytest

import deformable as dm
from deformable.io import CHECKPOINT_KEYS, CheckpointWriter, load_checkpoint, save_checkpoint

META = dict(scene="flag", config='scene = "flag"\n', backend="fd", dt=1e-3, nodes=(4, 5))


def test_a_checkpoint_reads_back_what_was_saved(tmp_path, rng):
    state = dm.State(t=0.25, X=rng.normal(size=(20, 3)), V=rng.normal(size=(20, 3)), step=250)
    X0 = rng.normal(size=(20, 3))
    path = save_checkpoint(tmp_path / "c.npz", state, X0, **META)
    assert [p.name for p in tmp_path.iterdir()] == ["c.npz"]  # no temporary file left
    ck = load_checkpoint(path)
    assert set(ck) == set(CHECKPOINT_KEYS) | {"A", "memory"} and ck["A"] is None  # no acceleration (semi-implicit)
    assert ck["memory"] is None  # none given
    assert (ck["t"], ck["step"], ck["scene"], ck["config"], ck["backend"], ck["dt"], ck["nodes"]) == (
        0.25, 250, "flag", META["config"], "fd", 1e-3, (4, 5))
    for key, value in (("X", state.X), ("V", state.V), ("X0", X0)):
        np.testing.assert_array_equal(ck[key], value)
    with_a = dm.State(t=0.25, X=state.X, V=state.V, step=250, A=rng.normal(size=(20, 3)))
    np.testing.assert_array_equal(load_checkpoint(save_checkpoint(tmp_path / "a.npz", with_a, X0, **META))["A"],
                                  with_a.A)
    memory = {"dt_now": 0.125, "accepted": 3, "rejected": 1, "newton_floor": 2.5e-11}
    assert load_checkpoint(save_checkpoint(tmp_path / "m.npz", with_a, X0, memory=memory, **META))["memory"] == memory


def test_what_is_not_a_checkpoint_is_a_value_error(tmp_path):
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"not a checkpoint")
    with pytest.raises(ValueError, match="cannot read checkpoint"):
        load_checkpoint(junk)
    with pytest.raises(ValueError, match="cannot read checkpoint"):
        load_checkpoint(tmp_path / "missing.npz")
    np.savez(tmp_path / "other.npz", X=np.zeros(3))
    with pytest.raises(ValueError, match="is not a checkpoint: missing V"):
        load_checkpoint(tmp_path / "other.npz")


def test_the_writer_saves_every_k_steps(tmp_path):
    X0 = np.zeros((20, 3))
    writer = CheckpointWriter(tmp_path, "run", 3, X0, **META)
    for step in range(1, 8):
        writer.handle(dm.State(t=step * 1e-3, X=X0 + step, V=X0, step=step))
    assert [p.name for p in writer.written] == ["run-0000003.npz", "run-0000006.npz"]
    assert load_checkpoint(writer.written[-1])["X"][0, 0] == 6
    with pytest.raises(ValueError, match="checkpoint-every must be a positive integer"):
        CheckpointWriter(tmp_path, "run", 0, X0, **META)
