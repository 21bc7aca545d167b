"""The README's library example runs as written, and so does its FE drop-in."""

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def library_examples() -> list[str]:
    """The python blocks of the README's library example section: FD, then FE on the same scene."""
    section = README.read_text().split("## Library example", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, re.S)


def test_readme_library_examples_run_as_printed_on_both_backends(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    fd, fe, simulation = library_examples()
    assert len([line for line in fd.splitlines() if line.strip()]) <= 9
    namespace = {}
    exec(compile(fd, "README.md (FD)", "exec"), namespace)
    out = capsys.readouterr().out
    assert "steps to t = 1 s" in out and "Energy(stretching=" in out
    assert "FEModel" in fe and "FDModel" not in fe
    exec(compile(fe, "README.md (FE)", "exec"), namespace)  # the FE block uses the FD block's scene
    out = capsys.readouterr().out
    assert "steps to t = 1 s" in out and "Energy(stretching=" in out
    assert type(namespace["model"]).__name__ == "FEModel"
    assert namespace["s"].G.shape == (2, 2, 2) and namespace["s"].r.shape == (2, 3)
    exec(compile(simulation, "README.md (Simulation)", "exec"), namespace)
    out = capsys.readouterr().out
    assert "Simulation('hanging', backend='fe', nodes=17x17" in out and "steps to t = 0.1 s" in out
    assert (tmp_path / "runs" / "hanging-fe" / "hanging.toml").is_file()


def test_the_output_api_of_the_readme_writes_a_series_into_a_new_folder(tmp_path):
    import numpy as np

    import deformable as dm
    from fdmodel import FDModel

    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(5, 5)), dm.Material(mu=0.1, gamma=0.05, eta=np.full((2, 2), 50.0), xi=np.full((2, 2), 1e-3)),
                     forces=[dm.Gravity()], constraints=[dm.Pin(["top-left", "top-right"])], force_model="variational")
    model = FDModel(scene)
    writer = dm.XDMFWriter(tmp_path / "out" / "cloth.xdmf", interval=0.02)
    dm.TimeStepper(model, dt=0.01).run(model.initial_state(), t_end=0.1, trackers=[writer])
    writer.close()
    cells, frames = dm.read_series(tmp_path / "out" / "cloth.xdmf")
    assert [t for t, *_ in frames] == [0.0, 0.02, 0.04, 0.06, 0.08, 0.1]  # exact frame times, in seconds
    assert cells.shape == (16, 4) and frames[-1][1].shape == (25, 3)


def test_readme_quick_start_has_two_commands():
    block = re.search(r"## Quick start\n\n```bash\n(.*?)```", README.read_text(), re.S).group(1)
    commands = [line for line in block.splitlines() if line.strip()]
    assert len(commands) == 2 and "deformable validate" in commands[0] and "pytest" in commands[1]
