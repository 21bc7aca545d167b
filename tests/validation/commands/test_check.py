"""``deformable check``: the paper's compatibility test on a scene's rest state, from the command line."""

import pytest

from deformable import scenes
from validation.commands import main


def _check(argv, capsys):
    code = main(["check", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_every_shipped_scene_has_a_compatible_rest_state(name, capsys):
    code, out, err = _check([name, "--grid", "9x9"], capsys)
    assert code == 0 and out.startswith(f"{name}: rest state compatible") and not err


@pytest.mark.parametrize("curvature, code, verdict", [((2.0, 0.0), 0, "compatible"), ((1.0, 1.0), 1, "NOT compatible")])
def test_a_rest_curvature_is_a_cylinder_or_no_surface(tmp_path, capsys, curvature, code, verdict):
    path = tmp_path / "curled.toml"
    path.write_text(f'scene = "curtain"\nrest_curvature = [{curvature[0]}, {curvature[1]}]\n')
    got, out, err = _check([str(path), "--grid", "17x17"], capsys)
    assert got == code and out.startswith(f"curtain: rest state {verdict} ") and not err
    assert "nan" not in out and "inf" not in out
    assert ("FAIL" in out) == (code == 1)


@pytest.mark.parametrize("argv, message", [
    (["tablecloth"], "unknown scene 'tablecloth'"),
    (["curtain", "--rtol", "2"], "--rtol must be a number in (0, 1)"),
    (["curtain", "--rtol", "tight"], "--rtol must be a number in (0, 1)"),
    (["curtain", "--grid", "5x5"], "at least 9 points a side"),
    (["curtain", "--grid", "5by5"], "malformed grid"),
])
def test_bad_input_is_one_line_exit_2(argv, message, capsys):
    code, out, err = _check(argv, capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and message in err and not out
