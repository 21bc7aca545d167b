"""The README as a front page: its quick start is what CI runs, its commands parse, its links lead to files, and
its library example runs as written; so do the user guide's examples (docs/guide.md) that it links to."""

import re
import shlex
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
GUIDE = ROOT / "docs" / "guide.md"


def python_blocks(path: Path, heading: str) -> list[str]:
    """The python blocks of the section ``## heading`` of the markdown file ``path``."""
    section = path.read_text().split(f"\n## {heading}\n", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, re.DOTALL)


def test_readme_library_example_runs_a_shipped_scene_in_five_lines(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (simulation,) = python_blocks(README, "Library example")
    assert len([line for line in simulation.splitlines() if line.strip()]) <= 5
    namespace = {}
    exec(compile(simulation, "README.md (Simulation)", "exec"), namespace)
    out = capsys.readouterr().out
    assert "Simulation('hanging', backend='fe', nodes=17x17" in out and "steps to t = 0.1 s" in out
    assert "6 frames" in out  # t = 0, 0.02, ..., 0.1
    folder = tmp_path / "runs" / "hanging-fe"
    assert (folder / "hanging.toml").is_file() and (folder / "hanging.xdmf").is_file()
    assert len(list(folder.glob("hanging-checkpoint-*.npz"))) == 2  # 20 steps, one every 10
    assert type(namespace["sim"].model).__name__ == "FEModel"
    s = namespace["s"]  # model.sample at two parameter points: r (P, 3), G and B (P, 2, 2)
    assert s.r.shape == (2, 3) and s.G.shape == (2, 2, 2) and s.B.shape == (2, 2, 2)


def test_the_guides_library_example_runs_as_printed_on_both_backends(capsys):
    fd, fe = python_blocks(GUIDE, "Library")
    assert len([line for line in fd.splitlines() if line.strip()]) <= 9
    namespace = {}
    exec(compile(fd, "docs/guide.md (FD)", "exec"), namespace)
    out = capsys.readouterr().out
    assert "steps to t = 1 s" in out and "Energy(stretching=" in out
    assert "FEModel" in fe and "FDModel" not in fe
    exec(compile(fe, "docs/guide.md (FE)", "exec"), namespace)  # the FE block uses the FD block's scene
    out = capsys.readouterr().out
    assert "steps to t = 1 s" in out and "Energy(stretching=" in out
    assert type(namespace["model"]).__name__ == "FEModel"
    assert namespace["s"].G.shape == (2, 2, 2) and namespace["s"].r.shape == (2, 3)


def test_the_output_api_of_the_guide_writes_a_series_into_a_new_folder(tmp_path):
    import numpy as np

    import deformable as dm
    from fdmodel import FDModel

    assert 'trackers=[dm.XDMFWriter("out/cloth.xdmf", interval=0.02)]' in GUIDE.read_text()
    scene = dm.Scene(dm.Sheet(size=(1.0, 1.0), nodes=(5, 5)), dm.Material(mu=0.1, gamma=0.05, eta=np.full((2, 2), 50.0), xi=np.full((2, 2), 1e-3)),
                     forces=[dm.Gravity()], constraints=[dm.Pin(["top-left", "top-right"])], force_model="variational")
    model = FDModel(scene)
    writer = dm.XDMFWriter(tmp_path / "out" / "cloth.xdmf", interval=0.02)
    dm.TimeStepper(model, dt=0.01).run(model.initial_state(), t_end=0.1, trackers=[writer])
    writer.close()
    cells, frames = dm.read_series(tmp_path / "out" / "cloth.xdmf")
    assert [t for t, *_ in frames] == [0.0, 0.02, 0.04, 0.06, 0.08, 0.1]  # exact frame times, in seconds
    assert cells.shape == (16, 4) and frames[-1][1].shape == (25, 3)


def quick_start() -> list[str]:
    block = re.search(r"## Quick start\n\n```bash\n(.*?)```", README.read_text(), re.DOTALL).group(1)
    return [line.split("#")[0].strip() for line in block.splitlines() if line.strip()]


def test_readme_quick_start_is_a_venv_then_two_commands_the_second_what_ci_runs():
    venv, validate, tests = quick_start()
    assert venv == "python -m venv .venv && . .venv/bin/activate"
    assert validate == "pip install . && deformable validate --quick"
    install, command = tests.split(" && ")
    ci = (ROOT / ".ci" / "run").read_text()
    ci_command = next(line.split("#")[0].strip() for line in ci.splitlines()
                      if "# the README's test command" in line and not line.lstrip().startswith("#"))
    assert command == ci_command == "pytest"
    extra = re.fullmatch(r'pip install "(\.\[\w+\])"', install).group(1)
    assert f'python -m pip install --quiet "{extra}"' in ci  # CI installs what the README installs


def readme_commands() -> list[str]:
    """Every command the README names: its code spans and its bash block's lines that start with one."""
    text = re.sub(r"\s+", " ", re.sub(r"```.*?```", "", README.read_text(), flags=re.DOTALL))  # spans across lines
    spans = re.findall(r"`([^`]+)`", text) + quick_start()
    commands = [part.strip() for span in spans for part in span.split(" && ")]
    return [c for c in commands if c.split(" ")[0] in ("deformable", "pip", "python")]


def test_every_command_of_the_readme_parses_and_names_what_exists():
    from validation.commands import build_parser, main, parse

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    commands = readme_commands()
    assert "deformable scenes" in commands and f"pip install {project['name']}" in commands
    for command in commands:
        argv = shlex.split(command)
        if argv[0] == "deformable":
            if not any(word.isupper() for word in argv[1:]):  # deformable run SCENE: a placeholder
                parse(build_parser(), argv[1:])
        elif argv[:2] == ["pip", "install"]:
            for requirement in argv[2:]:
                extras = re.fullmatch(r"\.(?:\[(\w+(?:,\w+)*)\])?", requirement)
                if extras:
                    assert set((extras.group(1) or "").split(",")) - {""} <= set(project["optional-dependencies"])
                else:
                    assert requirement == project["name"], command
        elif argv[0] == "python":
            assert argv[1] == "-m" or (ROOT / argv[1]).is_file(), command
    assert main(["scenes"]) == 0


def test_every_link_of_the_readme_leads_to_a_file_of_the_repository():
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)\s]*)?\)", README.read_text())
    local = [link for link in links if "://" not in link]
    assert "docs/guide.md" in local and "docs/scenes/curtain.gif" in local
    assert [link for link in local if not (ROOT / link).exists()] == []
