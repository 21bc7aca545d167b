"""Every script of examples/ runs as ``python examples/X.py OUT``, writes its PNG and prints a sensible result.

Each example runs in a subprocess with a temporary output folder; the checks
read the numbers it prints and hold them to what the physics or the theory
says (docs/design.md), not to what the script happened to give.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

#: the slower scripts, whose subjects have unit tests of their own (sweeps, energy models, series, scene files,
#: FD against FE, the elastica): their printed numbers are checked under ``pytest -m slow``; that each of them
#: runs and draws its picture CI checks in the documentation build, whose gallery runs every script
#: (docs/build.py fails on an example that fails or draws nothing). The default run stays under 2 minutes.
IN_THE_GALLERY = pytest.mark.slow


def run_example(name: str, out: Path, env: dict | None = None, arg: bool = True) -> str:
    """Run examples/<name>.py (output folder ``out`` as its argument, or through ``env``); returns its stdout."""
    proc = subprocess.run([sys.executable, str(EXAMPLES / f"{name}.py"), *([str(out)] if arg else [])],
                          cwd=out.parent, env={**os.environ, "MPLBACKEND": "Agg", **(env or {})},
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"{name} exited {proc.returncode}:\n{proc.stdout}\n{proc.stderr}"
    return proc.stdout


def number(pattern: str, text: str) -> float:
    """The number that ``pattern``'s one group matches in ``text`` (the pattern must match)."""
    match = re.search(pattern, text)
    assert match, f"{pattern!r} not in the output:\n{text}"
    return float(match.group(1))


def png(path: Path) -> None:
    assert path.is_file() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"


@pytest.fixture
def out(tmp_path):
    return tmp_path / "out"


def test_every_example_has_a_test():
    tested = {name[len("test_"):] for name in globals() if name.startswith("test_")}
    scripts = {p.stem for p in EXAMPLES.glob("*.py")}
    assert len(scripts) >= 8 and scripts <= tested, f"untested examples: {sorted(scripts - tested)}"


@IN_THE_GALLERY
def test_custom_scene(out):
    text = run_example("custom_scene", out)
    assert "finished" in text
    sag = number(r"centre sag ([\d.e+-]+) m", text)
    assert 0.02 < sag < 0.5, "a 1 m hammock under its weight and 0.5 N sags by centimetres to decimetres"
    assert number(r"max speed ([\d.e+-]+) m/s", text) < 0.01, "damped for 3 s, the hammock is at rest"
    png(out / "custom_scene.png")


@IN_THE_GALLERY
def test_custom_energy(out):
    text = run_example("custom_energy", out)
    for backend in ("FD", "FE"):
        assert number(rf"{backend}: gradient error ([\d.e+-]+)", text) < 1e-6, "the exact gradient of its energy"
    drops = {b: (number(rf"{b} \d+x\d+ nodes: the hem hangs ([\d.]+) mm lower \(saturating\)", text),
                 number(rf"{b} \d+x\d+ nodes: .* against ([\d.]+) mm \(eq. 13\)", text)) for b in ("FD", "FE")}
    for b, (saturating, eq13) in drops.items():
        assert saturating > eq13 > 0, f"{b}: a membrane whose tension saturates lets the cloth hang lower"
    assert abs(drops["FD"][0] - drops["FE"][0]) < 0.05 * drops["FE"][0], "FD and FE agree on the new energy"
    assert text.count("finished (saturating), finished (eq. 13)") == 2
    png(out / "custom_energy.png")


@IN_THE_GALLERY
def test_fd_vs_fe(out):
    text = run_example("fd_vs_fe", out)
    assert text.count("finished") == 2
    fd, fe = (number(rf"{b}: .*free corner at z = ([\d.e+-]+) m", text) for b in ("FD", "FE"))
    assert -1.1 < fd < -0.3 and -1.1 < fe < -0.3, "the free corner falls (about g t^2 / 2 = 0.8 m by 0.4 s)"
    gap = number(r"differ by at most ([\d.e+-]+) m", text)
    assert 0 < gap < 0.05, "on the same 9 x 9 grid FD and FE agree in positions to a few centimetres"
    png(out / "fd_vs_fe.png")


@IN_THE_GALLERY
def test_curling_strip(out):
    text = run_example("curling_strip", out)
    h = number(r"\(h = ([\d.e+-]+) m\)", text)
    fd = number(r"FD: .*error ([\d.e+-]+) m", text)
    fe = number(r"FE: .*error ([\d.e+-]+) m", text)
    assert fd < h, "FD's clamp shifts the clamped line by h: a tip error of order h"
    assert fe < 1e-4, "FE's tip error is O(h^3) with a small constant"
    png(out / "curling_strip.png")


@IN_THE_GALLERY
def test_cantilever_elastica(out):
    text = run_example("cantilever_elastica", out)
    fd = number(r"FD .*elastica ([\d.e+-]+) L", text)
    fe = number(r"FE .*elastica ([\d.e+-]+) L", text)
    assert fd < 0.05 and fe < 5e-3, "both backends follow the elastica; FE closer on fewer nodes"
    assert number(r"\n\s+4.00\s+([\d.]+)", text) == pytest.approx(0.66996, abs=2e-5), "w/L of the literature"
    png(out / "cantilever_elastica.png")


@IN_THE_GALLERY
def test_read_back(out):
    text = run_example("read_back", out, env={"EXAMPLES_OUT": str(out)}, arg=False)  # the folder from the env var
    assert number(r"meshio: (\d+) frames", text) == 21, "a frame every 0.05 s over 1 s, and the first"
    assert "displacement" in text and "speed" in text
    assert number(r"pyvista: (\d+) time steps", text) == 21 or "pyvista: not installed" in text
    if "pyvista: rendered" in text:
        png(out / "read_back_pyvista.png")
    assert (out / "read_back" / "hanging.xdmf").is_file() and (out / "read_back" / "hanging.h5").is_file()
    png(out / "read_back.png")


@pytest.mark.slow
def test_read_back_without_pyvista(out, tmp_path):
    hidden = tmp_path / "hide"  # a pyvista package that fails to import, first on the path
    (hidden / "pyvista").mkdir(parents=True)
    (hidden / "pyvista" / "__init__.py").write_text("raise ImportError('pyvista hidden by the test')\n")
    path = os.pathsep.join(filter(None, [str(hidden), os.environ.get("PYTHONPATH")]))
    text = run_example("read_back", out, env={"PYTHONPATH": path})
    assert [line for line in text.splitlines() if line.startswith("pyvista")] == \
        ["pyvista: not installed, skipping its part (pip install pyvista)"]
    assert number(r"meshio: (\d+) frames", text) == 21
    png(out / "read_back.png")
    assert not (out / "read_back_pyvista.png").exists()


@IN_THE_GALLERY
def test_convergence(out):
    text = run_example("convergence", out)
    theory = {"FD G": 1, "FD B": 1, "FE G": 3, "FE B": 2}
    for name, p in theory.items():
        observed = number(rf"{name}: .*observed order ([\d.e+-]+)", text)
        assert p - 0.3 <= observed <= p + 0.3, f"{name}: observed order {observed}, theory {p}"
    png(out / "convergence.png")


@IN_THE_GALLERY
def test_sweep(out):
    text = run_example("sweep", out)
    assert "15 cases, 15 run now" in text
    assert "finished" in text and "diverged" in text
    finished = number(r"finished runs up to ([\d.]+)", text)
    diverged = number(r"diverged runs from ([\d.]+)", text)
    assert finished < diverged <= 1.0, "the step diverges above its stretching bound, and only there"
    png(out / "sweep" / "sweep.png")
    again = run_example("sweep", out)  # the stored cases are taken, none runs again
    assert "15 cases, 0 run now, 15 from" in again


@IN_THE_GALLERY
def test_toml_scene(out):
    text = run_example("toml_scene", out)
    assert "changed from its defaults" in text and "wind = 6.0" in text and "nodes = (10, 6)" in text
    assert "finished" in text
    assert 0 < number(r"across the plane ([\d.e+-]+) m", text) < 0.6
    assert (out / "toml_scene.toml").is_file()
    png(out / "toml_scene.png")


@IN_THE_GALLERY
def test_koiter_plate(out):
    """Theory: bicubic Hermite elements give point values at order 4 (docs/design.md); the plate's D carries
    1 - nu^2. FD's first order at nu > 0 is a finding the script prints, not a theory this asserts."""
    text = run_example("koiter_plate", out)
    assert number(r"D = ([\d.e+-]+) N m", text) == pytest.approx(1e6 * 1e-2**3 / (12 * (1 - 0.3**2)), rel=1e-5)
    assert 3.5 <= number(r"FE: observed order ([\d.e+-]+)", text) <= 4.5
    assert number(r"FE 17 nodes a side: relative error ([\d.e+-]+)", text) <= 1e-3
    png(out / "koiter_plate.png")


@IN_THE_GALLERY
def test_mesh_obstacle(out):
    """A cloth dropped on a stool read from an OBJ file: never closer than 0 to it at any step, and its corners hang
    below the seat's edge, at most the cloth's free reach beyond the seat's corner (0.495 - 0.212 m)."""
    text = run_example("mesh_obstacle", out)
    assert number(r"smallest clearance (\S+) m", text) > 0
    assert 0.05 < number(r"corners hang (\S+) m below the seat", text) < 0.495 - 0.212
    assert number(r"(\d+) triangles read", text) == 60
    png(out / "mesh_obstacle.png")
