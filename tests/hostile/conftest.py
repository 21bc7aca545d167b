"""The hostile tests see a machine with 1 GB of memory available, so that "beyond memory" is the same everywhere."""

import pytest

from validation.commands import main


def run_command(argv, capsys):
    """``deformable ARGV`` in this process: (exit code, stdout, stderr)."""
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def refused(code, err, message):
    """A refusal: exit 2, one line on stderr holding ``message``, no traceback."""
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1 and message in err, err
    assert "Traceback" not in err


@pytest.fixture(autouse=True)
def one_gigabyte(monkeypatch):
    monkeypatch.setattr("deformable.limits.available_memory", lambda: 1e9)
