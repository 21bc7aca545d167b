"""One path from a scene config to a run (issue 46): ``deformable run`` and ``deformable sweep`` take the same grid,
model and dt for the same scene and backend (:class:`deformable.Simulation`), and read a grid the
same way (:func:`validation.commands.run.parse_grid`: ``nodes=12x12``, ``[12, 12]``, ``12``).

The runs are the hanging scene on its own grid (FD 32 x 32 nodes; FE 16 x 16 elements, 17 x 17 nodes) for three
steps of 5 ms, or 12 x 12 nodes for two steps.
"""

import hashlib
import json
import tomllib

import numpy as np
import pytest

from deformable import scenes
from deformable.io import load_checkpoint
from validation.commands import main
from validation.commands.run import parse_grid, parse_overrides
from validation.commands.sweep import parse_axis

#: three steps of the hanging scene's dt (5 ms)
T_END, STEPS = "0.015", 3
#: the hanging scene's grid (FD nodes, 32 x 32) taken in each backend's unit: FE half as many elements a side
HANGING = tuple(scenes.config("hanging").nodes)
OWN_GRID = {"fd": HANGING, "fe": tuple(round((n - 1) / 2) + 1 for n in HANGING)}


def _main(argv, capsys):
    code = main([*map(str, argv)])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("backend", ["fd", "fe"])
def test_run_and_sweep_take_the_same_grid_and_reach_the_same_state(backend, tmp_path, capsys):
    """The run's last checkpoint and the sweep's stored case: the same grid, time, steps and positions (bit for
    bit: the sweep stores a digest of the final X, (ndof, 3) m)."""
    run, sweep = tmp_path / "run", tmp_path / "sweep"
    code, _, err = _main(["run", "hanging", "--backend", backend, "--t-end", T_END, "--checkpoint-every", STEPS,
                          "--out", run, "-q"], capsys)
    assert code == 0, err
    code, _, err = _main(["sweep", "hanging", f"t_end={T_END}", "--backend", backend, "--out", sweep, "-q"], capsys)
    assert code == 0, err

    resolved = tomllib.loads((run / "hanging.toml").read_text())
    (case,) = [json.loads(p.read_text()) for p in (sweep / "cases").glob("*.json")]
    own = OWN_GRID[backend]
    assert tuple(resolved["nodes"]) == tuple(case["fields"]["nodes"]) == own
    assert resolved["dt"] == case["dt"] and resolved["run"]["backend"] == case["backend"] == backend

    final = load_checkpoint(run / f"hanging-checkpoint-{STEPS:07d}.npz")
    assert case["status"] == "finished" and case["steps"] == final["step"] == STEPS and case["t"] == final["t"]
    assert tuple(final["nodes"]) == own and final["backend"] == backend
    assert hashlib.sha1(np.ascontiguousarray(final["X"]).tobytes()).hexdigest() == case["state_sha1"]


def test_run_takes_a_grid_as_sweep_does(tmp_path, capsys):
    """``nodes=12x12`` runs; ``nodes=[12,12]`` (TOML) and ``--grid 12x12`` resolve the same config."""
    configs = []
    for k, grid in enumerate([["nodes=12x12"], ["nodes=[12,12]"], ["nodes=[12, 12]"], ["--grid", "12x12"]]):
        out = tmp_path / str(k)
        code, summary, err = _main(["run", "hanging", *grid, "--steps", "2", "--out", out], capsys)
        assert code == 0, err
        assert "2 steps to t = 0.01 s" in summary and "12x12 fd" in summary
        configs.append(tomllib.loads((out / "hanging.toml").read_text()))
    assert configs[0]["nodes"] == [12, 12] and all(c == configs[0] for c in configs)


def test_one_parser_reads_a_grid_for_run_and_sweep():
    base = scenes.config("hanging")
    for text in ("12x12", "[12,12]", " [ 12 , 12 ] ", "12X12", "12"):
        assert parse_overrides([f"nodes={text}"]) == {"nodes": (12, 12)}
        assert parse_axis(base, f"nodes={text}") == ("nodes", ((12, 12),))
    assert parse_axis(base, "nodes=[12, 10],8x6,8") == ("nodes", ((12, 10), (8, 6), (8, 8)))
    assert parse_grid("[16, 8]") == parse_grid("16x8") == (16, 8)


@pytest.mark.parametrize("command", ["run", "sweep"])
@pytest.mark.parametrize("value, message", [
    ("12by12", "nodes: malformed grid '12by12'"),
    ("[12,", "nodes: malformed grid '[12"),
    ("[inf, 8]", "nodes: malformed grid '[inf, 8]'"),
    ("2x12", "nodes: grid '2x12' needs at least 3 nodes a side"),
])
def test_a_bad_grid_is_one_line_naming_the_field_and_value(command, value, message, tmp_path, capsys):
    code, _, err = _main([command, "hanging", f"nodes={value}", "--out", tmp_path / "out"], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and message in err, err
    assert not (tmp_path / "out").exists()
