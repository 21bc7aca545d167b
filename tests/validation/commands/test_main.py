"""The ``deformable`` entry point (validation.commands): help, version, and one-line errors."""

import pytest

import deformable
from validation.commands import main


def test_no_command_prints_the_help_with_every_command(capsys):
    assert main([]) == 0
    out = capsys.readouterr().out
    assert all(name in out for name in ("run", "validate", "bench"))


def test_version(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["--version"])
    assert exit_.value.code == 0 and capsys.readouterr().out.strip() == f"deformable {deformable.__version__}"


def test_an_unknown_command_is_one_line_and_exit_2(capsys):
    assert main(["simulate"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "invalid choice: 'simulate'" in err
