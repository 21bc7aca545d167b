"""run.md's environment (issue 47, point 6): versions from importlib.metadata, the BLAS and OpenMP libraries from
threadpoolctl, the git commit when there is one; never an error."""

import json
import re
from pathlib import Path

import numpy  # noqa: F401  (loads its BLAS)

from deformable.checks import DISTRIBUTION
from validation.harness import report
from validation.harness.report import environment, git_commit, thread_pools, versions, write_study
from validation.harness.study import StudyResult

ROOT = Path(__file__).resolve().parents[3]


def test_versions_name_every_package_the_results_depend_on(monkeypatch):
    found = versions()
    assert list(found)[:2] == ["python", DISTRIBUTION]
    for name in ("numpy", "scipy", "scikit-fem", "numba", "ipctk", "pypardiso", "matplotlib", "meshio", "h5py"):
        assert isinstance(found[name], str) and found[name], name
    assert found["numba"] != "not installed"
    monkeypatch.setattr(report, "PACKAGES", ("numpy", "no-such-distribution-here"))
    assert versions()["no-such-distribution-here"] == "not installed"


def test_thread_pools_name_the_blas():
    pools = thread_pools()
    blas = [p for p in pools if p["user_api"] == "blas"]
    assert blas and all(set(p) == {"user_api", "internal_api", "version", "num_threads"} for p in pools)
    assert blas[0]["internal_api"] and blas[0]["num_threads"] >= 1


def test_the_git_commit_or_not_a_git_checkout_never_an_error(tmp_path, monkeypatch):
    if (ROOT / ".git").exists():
        assert re.fullmatch(r"[0-9a-f]{40}", git_commit(ROOT))
    monkeypatch.setenv("GIT_CEILING_DIRECTORIES", str(tmp_path.parent))
    assert git_commit(tmp_path) == "not a git checkout"
    monkeypatch.setenv("PATH", str(tmp_path))  # no git at all
    assert git_commit(ROOT) == "not a git checkout"


def test_run_md_and_run_json_hold_the_environment(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # not a git checkout
    monkeypatch.setenv("GIT_CEILING_DIRECTORIES", str(tmp_path.parent))
    res = StudyResult("demo", "a synthetic study")
    res.wall_time = 1.5
    folder = write_study(res, tmp_path / "out")
    page = (folder / "run.md").read_text()
    assert "Wall time 1.5 s." in page and "## Environment" in page
    for name in ("| python |", f"| {DISTRIBUTION} |", "| numba |", "| ipctk |", "| pypardiso |", "| h5py |",
                 "| git commit | not a git checkout |", "| thread pool | library | version | threads |", "| blas |"):
        assert name in page, name
    run = json.loads((folder / "run.json").read_text())
    assert run["git_commit"] == "not a git checkout" and run["thread_pools"] == environment()["thread_pools"]
    assert run["versions"]["numpy"] == versions()["numpy"]
    assert "Environment" not in (folder / "summary.md").read_text()
