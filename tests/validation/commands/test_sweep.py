"""``deformable sweep``: one row per case, failures as rows, restarts that run only what is missing.

Every sweep here is tiny (6 x 6 nodes, 20 steps, or 10 x 10 nodes for the sweep that is killed) and
asserts no physics: only what the table holds, which cases ran, and that executors agree.
"""

import csv
import subprocess
import sys

import numpy as np
import psutil
import pytest

from deformable import scenes
from validation.commands import main
from validation.commands.sweep import parse_axis
from validation.harness import sweep as sweep_module
from validation.harness.sweep import FINAL, STATUSES

TINY = ["hanging", "nodes=6x6", "t_end=0.02"]


def sweep(tmp_path, *args):
    return main(["sweep", *TINY, *args, "--out", str(tmp_path / "out")])


def rows(tmp_path) -> list[dict]:
    with open(tmp_path / "out" / "sweep.csv", newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture
def runs(monkeypatch):
    """The keys of the cases actually run in this process (the sweep's case function, counted)."""
    ran = []
    real = sweep_module.run_case

    def counted(case):
        ran.append(case.key)
        return real(case)

    monkeypatch.setattr(sweep_module, "run_case", counted)
    return ran


# -- bad input -----------------------------------------------------------------------
@pytest.mark.parametrize("args, message", [
    (["eta=abc"], "sweep value of eta must be a number, got 'abc'"),
    (["etta=1,2"], "unknown key 'etta' for scene 'hanging'"),
    (["eta"], "sweep values must be KEY=V1,V2,..."),
    (["scene=flag"], "the scene itself is not a sweep key"),
    (["eta=1:2"], "must be START:STOP:NUM or START:STOP:NUM:log"),
    (["eta=1:2:x"], "needs NUM >= 2 values, got 'x'"),
    (["xi=0:1:3:log"], "a log range needs START and STOP > 0"),
    (["nodes=2x2"], "needs at least 3 nodes a side"),
    (["size=1x2x3"], "sweep value of size must be AxB or A"),
    (["eta=1", "eta=2"], "sweep key 'eta' is given twice"),
    (["--backend", "fd,fx"], "unknown backend 'fx'"),
    (["--measure", "kinetic,nope"], "unknown measure 'nope'"),
    (["--scheduler", "local:0"], "needs a positive number of workers"),
    (["--scheduler", "nowhere.json"], "is none of them (no such file)"),
    (["--jobs", "2", "--scheduler", "local:2"], "not allowed with argument"),
    (["--jobs", "0"], "jobs must be a positive integer"),
])
def test_bad_input_is_one_line_exit_2_and_writes_nothing(args, message, tmp_path, capsys):
    code = sweep(tmp_path, "eta=10,20", *args)
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and message in err, err
    assert not (tmp_path / "out").exists()


def test_an_unknown_scene_is_one_line(tmp_path, capsys):
    assert main(["sweep", "hangin", "eta=1,2", "--out", str(tmp_path / "out")]) == 2
    assert "unknown scene 'hangin'" in capsys.readouterr().err and not (tmp_path / "out").exists()


def test_without_dask_scheduler_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    assert sweep(tmp_path, "eta=10,20", "--scheduler", "local:2") == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and 'pip install ".[distributed]"' in err
    assert not (tmp_path / "out").exists()


def test_values_ranges_and_grids_parse_by_the_field_type():
    base = scenes.config("hanging")
    assert parse_axis(base, "eta=10:30:3,5,10") == ("eta", (10.0, 20.0, 30.0, 5.0))
    key, xis = parse_axis(base, "xi=1e-4:1e-2:3:log")
    assert key == "xi" and np.allclose(xis, [1e-4, 1e-3, 1e-2], rtol=1e-12, atol=0)
    assert parse_axis(base, "nodes=8,6x10") == ("nodes", ((8, 8), (6, 10)))
    assert parse_axis(base, "size=1x1.5,2") == ("size", ((1.0, 1.5), (2.0, 2.0)))
    assert parse_axis(base, "force_model=tpbf87,frozen") == ("force_model", ("tpbf87", "frozen"))


# -- the table -----------------------------------------------------------------------
def test_one_row_per_case_failures_are_rows_and_the_exit_code_is_1(tmp_path, capsys):
    code = sweep(tmp_path, "eta=20,40", "mu=-1,0.2", "--backend", "fd,fe", "--measure", "kinetic,displacement")
    assert code == 1  # the cases at mu = -1 failed (the scene refuses them); the others are rows as well
    table = rows(tmp_path)
    assert len(table) == 8 and [r["backend"] for r in table] == ["fd"] * 4 + ["fe"] * 4
    assert [(r["eta"], r["mu"]) for r in table[:4]] == [("20.0", "-1.0"), ("20.0", "0.2"), ("40.0", "-1.0"),
                                                        ("40.0", "0.2")]
    failed = [r for r in table if r["mu"] == "-1.0"]
    assert all(r["status"] == "failed" and "mu" in r["message"] and "-1.0" in r["message"] for r in failed)
    others = [r for r in table if r["mu"] == "0.2"]
    assert all(r["status"] in STATUSES and r["status"] != "failed" for r in others)
    assert all(np.isfinite(float(r[col])) for r in others
               for col in ("energy (J)", "max stretch", "max speed (m/s)", "kinetic energy (J)", "max displacement (m)"))
    out = tmp_path / "out"
    assert (out / "sweep.png").read_bytes()[:4] == b"\x89PNG"  # two swept keys: a map
    assert "| failed |" in (out / "sweep.md").read_text()
    assert scenes.read_toml(out / "sweep.toml") == scenes.config("hanging")
    assert "8 cases (" in capsys.readouterr().out


def test_fail_on_error_exits_1_when_a_case_did_not_finish(tmp_path, capsys):
    assert sweep(tmp_path, "mu=-1,0.2", "--fail-on-error") == 1
    assert "1 of 2 cases did not finish" in capsys.readouterr().err
    assert len(rows(tmp_path)) == 2


def test_one_swept_key_makes_no_map_and_progress_counts_the_cases(tmp_path, capsys):
    assert sweep(tmp_path, "eta=20,40,80") == 0
    assert not (tmp_path / "out" / "sweep.png").exists()
    err = capsys.readouterr().err
    assert "1/3 cases done" in err and "about" in err and "3/3 cases done" in err


def test_a_scene_file_is_the_base(tmp_path):
    path = tmp_path / "small.toml"
    path.write_text('scene = "hanging"\nnodes = [6, 6]\nt_end = 0.02\neta = 30.0\n')
    assert main(["sweep", str(path), "xi=0,1e-3", "--out", str(tmp_path / "out")]) == 0
    assert [r["xi"] for r in rows(tmp_path)] == ["0.0", "0.001"]
    assert scenes.read_toml(tmp_path / "out" / "sweep.toml") == scenes.read_toml(path)


# -- restarts ------------------------------------------------------------------------
@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
def test_a_killed_sweep_started_again_runs_only_the_missing_cases(tmp_path, runs):
    out = tmp_path / "out"
    argv = ["sweep", "hanging", "nodes=10x10", "t_end=0.15", "eta=10,20,40,80,160,320", "--out", str(out)]
    code = "import sys; from validation.commands import main; sys.exit(main(sys.argv[1:]))"
    child = subprocess.Popen([sys.executable, "-c", code, *argv, "--jobs", "2"], stderr=subprocess.PIPE, text=True,
                             cwd=tmp_path)
    workers = []
    try:
        for line in child.stderr:  # one progress line per stored case (stderr is not a terminal)
            if "2/6 cases done" in line:
                workers = psutil.Process(child.pid).children()
                child.kill()  # SIGKILL: nothing runs on the way out
                break
    finally:
        child.kill()
        child.wait()
    assert len(workers) == 2
    _, alive = psutil.wait_procs(workers, timeout=10)
    for process in alive:
        process.kill()
    assert not alive, "the pool's workers outlived the killed sweep"
    stored = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in (out / "cases").glob("*.json")}
    assert 2 <= len(stored) < 6, f"{len(stored)} cases stored when the sweep was killed"
    assert not (out / "sweep.csv").exists()

    assert main(argv) == 0  # serially, in this process, where the case function is counted
    assert len(runs) == 6 - len(stored), "the restart ran cases that were stored"
    assert not {f"{key}.json" for key in runs} & stored.keys()
    for name, (data, mtime) in stored.items():
        path = out / "cases" / name
        assert path.read_bytes() == data and path.stat().st_mtime_ns == mtime, f"{name} was written again"
    table = rows(tmp_path)
    assert [r["eta"] for r in table] == ["10.0", "20.0", "40.0", "80.0", "160.0", "320.0"]
    assert all(r["status"] in FINAL for r in table)


def test_a_restart_runs_failed_cases_new_values_and_missing_measures_again(tmp_path, runs):
    assert sweep(tmp_path, "eta=20,40", "mu=-1,0.2") == 1  # a case the scene refuses is a failed row
    assert len(runs) == 4
    runs.clear()
    assert sweep(tmp_path, "eta=20,40", "mu=-1,0.2") == 1  # a case the scene refuses is a failed row
    assert len(runs) == 2, "only the two failed cases run again"
    runs.clear()
    assert sweep(tmp_path, "eta=20,40,80", "mu=-1,0.2") == 1
    assert len(runs) == 4, "the failed cases and the two new ones"
    runs.clear()
    assert sweep(tmp_path, "eta=20,40,80", "mu=-1,0.2", "--measure", "bending") == 1
    assert len(runs) == 6, "every case: none has the new measure"
    assert len(rows(tmp_path)) == 6


def test_an_unreadable_stored_case_runs_again(tmp_path, runs):
    assert sweep(tmp_path, "eta=20,40") == 0
    first = sorted((tmp_path / "out" / "cases").glob("*.json"))[0]
    first.write_text(first.read_text()[:40])  # as if cut off (the sweep itself writes through a rename)
    runs.clear()
    assert sweep(tmp_path, "eta=20,40") == 0
    assert runs == [first.stem]


# -- executors -----------------------------------------------------------------------
@pytest.mark.slow  # a slow fault or a whole pipeline, run by pytest -m slow
def test_on_dask_the_numbers_are_those_of_a_serial_run(tmp_path, capsys, dask_scheduler):
    address, _ = dask_scheduler
    assert sweep(tmp_path, "eta=20,40", "mu=-1,0.2", "--scheduler", address, "--compare-serial") == 1
    out = capsys.readouterr().out
    assert f"on the Dask scheduler {address} (2 workers)" in out and "numbers bit-identical" in out, out
    assert len(rows(tmp_path)) == 4


def test_a_scene_in_a_named_fabric_sweeps_and_its_fabric_fields_need_the_fabric_dropped(tmp_path, capsys):
    """The shipped curtain is denim: every case of a sweep over it ran a config carrying the fabric and the fields
    it sets, refused as a clash (all cases failed). A case now carries the fabric alone; sweeping a field the
    fabric sets is refused in one line before any case runs, and fabric="" (the shell's fabric=) sweeps it."""
    out = tmp_path / "gather"
    assert main(["sweep", "curtain", "gather=0.5,0.4", "nodes=8x8", "t_end=0.01", "--out", str(out), "-q"]) == 0
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert [r["status"] for r in rows] == ["finished", "finished"]
    refused = tmp_path / "xi"
    assert main(["sweep", "curtain", "xi=1e-4,1e-3", "nodes=8x8", "t_end=0.01", "--out", str(refused)]) == 2
    err = capsys.readouterr().err
    assert "sweep key xi: the fabric 'denim' sets mu, eta, xi and shear" in err and "Traceback" not in err
    assert not refused.exists()
    dropped = tmp_path / "dropped"
    assert main(["sweep", "curtain", "fabric=", "xi=1e-4,1e-3", "nodes=8x8", "t_end=0.01", "--out", str(dropped),
                 "-q"]) == 0
    assert [r["status"] for r in csv.DictReader((dropped / "sweep.csv").open())] == ["finished", "finished"]
