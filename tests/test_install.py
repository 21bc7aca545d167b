"""The core install (``pip install .``) goes without VTK: nothing but drawing needs pyvista, and what draws says
in one line how to get it (pyproject.toml's ``render`` extra)."""

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from deformable.checks import extra
from deformable.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
#: run the command line as if pyvista and VTK were not installed (an import of either fails)
WITHOUT_VTK = ("import sys; sys.modules.update(pyvista=None, vtk=None, vtkmodules=None); "
               "from validation.commands import main; sys.exit(main(sys.argv[1:]))")


def without_vtk(*argv, cwd):
    return subprocess.run([sys.executable, "-c", WITHOUT_VTK, *argv], capture_output=True, text=True, cwd=cwd,
                          timeout=600)


def test_the_core_dependencies_leave_out_pyvista_and_vtk_and_the_render_extra_brings_them():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    core = " ".join(project["dependencies"]).lower()
    assert "pyvista" not in core and "vtk" not in core
    assert any(d.startswith("pyvista") for d in project["optional-dependencies"]["render"])


def test_a_missing_extra_is_one_line_naming_the_command_and_the_extra():
    with pytest.raises(InputError) as err:
        extra("no_such_module_of_deformable", "render", "deformable run --render")
    message = str(err.value)
    assert "\n" not in message and message.startswith("deformable run --render needs no_such_module_of_deformable")
    assert "pip install 'deformable-sheets[render]'" in message


def test_the_quick_validation_runs_without_vtk(tmp_path):
    done = without_vtk("validate", "statics", "--levels", "3", "--out", str(tmp_path / "reports"), cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "reports" / "statics" / "summary.md").is_file()


def test_the_viewer_without_vtk_says_how_to_install_it_in_one_line(tmp_path):
    done = without_vtk("view", "hanging", "--offscreen", "--frames", "1", cwd=tmp_path)
    assert done.returncode == 2 and done.stderr.strip().count("\n") == 0, done.stderr
    assert "pip install 'deformable-sheets[render]'" in done.stderr and "deformable view" in done.stderr
