"""``deformable fabrics``: the presets as a table; an unknown name is one line and exit code 2."""

import pytest

from deformable.physics.fabric import Fabric
from validation.commands import main
from validation.commands.fabrics import COLUMNS


def test_lists_every_preset_with_its_values(capsys):
    assert main(["fabrics"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert all(col in lines[0] for col in COLUMNS) and set(lines[1]) <= {"-", " "}
    body = {ln.split()[0]: ln for ln in lines[2:]}
    assert list(body) == list(Fabric.presets())
    denim = body["denim"].split()  # 324 g/m^2, T 411 / 2028 N/m, D 97.0 / 64.2 micro N m, c 3.12 / 2.72 cm
    assert denim[1:14] == ["324", "411", "/", "2028", "97.0", "/", "64.2", "3.12", "/", "2.72", "ARCSim",
                           "11oz-black-denim.json", "(Wang"]
    assert "authors' estimate" in body["paper"] and "1000000 / 1000000" in body["paper"]


def test_names_select_presets_in_the_order_given(capsys):
    assert main(["fabrics", "paper", "tshirt-knit"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [ln.split()[0] for ln in lines[2:]] == ["paper", "tshirt-knit"]


def test_an_unknown_name_is_one_line_and_exit_2(capsys):
    assert main(["fabrics", "denim", "silk"]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert len(err.splitlines()) == 1 and "fabric 'silk' is not a preset; known: blanket" in err
    assert captured.out == ""


@pytest.mark.parametrize("argv", [["--help"], ["fabrics", "--help"]])
def test_help_names_the_command(argv, capsys):
    with pytest.raises(SystemExit):
        main(argv)
    out = capsys.readouterr().out
    assert "fabrics" in out and ("density" in out or "denim" in out)
