"""The README's library example runs as written, and so does its FE drop-in."""

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def library_example() -> str:
    section = README.read_text().split("## Library example", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


@pytest.mark.parametrize("backend", ["FDModel", "FEModel"])
def test_readme_library_example_runs_on_both_backends(backend, capsys):
    code = library_example()
    assert len([line for line in code.splitlines() if line.strip()]) <= 9
    if backend == "FEModel":  # "FEModel(scene) from femodel is a drop-in replacement for FDModel(scene)"
        code = code.replace("from fdmodel import FDModel", "from femodel import FEModel").replace("FDModel(", "FEModel(")
    exec(compile(code, "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert "steps to t = 1 s" in out and "Energy(stretching=" in out


def test_readme_quick_start_has_two_commands():
    block = re.search(r"## Quick start\n\n```bash\n(.*?)```", README.read_text(), re.S).group(1)
    commands = [line for line in block.splitlines() if line.strip()]
    assert len(commands) == 2 and "deformable validate" in commands[0] and "pytest" in commands[1]
