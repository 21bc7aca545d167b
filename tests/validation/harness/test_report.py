"""The report writer on a small synthetic result."""

import csv
import json

import pytest

from validation.harness.report import markdown_table, writable_folder, write_index, write_study
from validation.harness.study import Figure, Line, Panel, StudyResult, Table


def synthetic():
    res = StudyResult("demo", "a synthetic study", config={"levels": 3})
    res.check("order of something", "order 2", "p = 2.01", True)
    res.check("another", "order 1", "p = 0.2", False)
    res.check("third", "exact", "0", True)
    res.tables.append(Table("numbers", "Some numbers", ("name", "h", "error"),
                            [("a", 0.5, 1e-2), ("b", 0.25, 2.5e-3), ("c | pipe", 0.125, float("nan"))]))
    res.figures.append(Figure("conv", "a convergence plot",
                              (Panel("demo", "h (m)", "error (m)", (Line("e", (0.5, 0.25), (1e-2, 2.5e-3)),),
                                     (2.0,)),)))
    res.findings.append("something noted")
    return res


def test_files_exist_tables_parse_and_counts_are_right(tmp_path):
    folder = write_study(synthetic(), tmp_path)
    for name in ("summary.md", "results.json", "run.md", "run.json", "numbers.csv", "conv.png"):
        assert (folder / name).is_file(), name
    summary = (folder / "summary.md").read_text()
    assert summary.rstrip().endswith("2 checks passed, 1 failed")
    assert summary.count("| PASS |") == 2 and summary.count("| **FAIL** |") == 1
    with (folder / "numbers.csv").open() as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["name", "h", "error"] and len(rows) == 4
    assert float(rows[2][2]) == 2.5e-3 and rows[3][2] == ""
    data = json.loads((folder / "results.json").read_text())
    assert data["passed"] == 2 and data["failed"] == 1 and data["config"] == {"levels": 3}
    assert "numpy" in json.loads((folder / "run.json").read_text())["versions"]
    assert data["tables"][0]["rows"][2][2] is None and "versions" not in data and "wall_time" not in data
    assert 5_000 < (folder / "conv.png").stat().st_size < 200_000
    index = write_index(tmp_path).read_text()
    assert "[demo](demo/summary.md)" in index and "2 checks passed, 1 failed" in index


def test_csvs_are_numeric_and_a_rerun_with_the_same_results_changes_only_the_run_files(tmp_path):
    import numpy as np
    import pandas as pd

    res = synthetic()
    res.tables.append(Table("numpy", "NumPy scalars", ("n", "x", "flag"),
                            [(np.int64(3), np.float64(0.125), np.bool_(True)), (4, np.float32(0.5), False)]))
    res.wall_time = 1.5
    folder = write_study(res, tmp_path)
    text = (folder / "numpy.csv").read_text()
    assert "np." not in text and text.splitlines()[1] == "3,0.125,True"
    frame = pd.read_csv(folder / "numpy.csv")
    assert frame["n"].dtype.kind == "i" and frame["x"].dtype.kind == "f" and frame["x"][0] == 0.125
    assert pd.read_csv(folder / "numbers.csv")["error"].dtype.kind == "f"  # NaN cells are empty, not "nan" text
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    res.wall_time = 7.25
    write_study(res, tmp_path)
    after = {p.name: p.read_bytes() for p in folder.iterdir()}
    assert sorted(before) == sorted(after)
    assert sorted(name for name in before if before[name] != after[name]) == ["run.json", "run.md"]
    assert json.loads(after["run.json"])["wall_time"] == 7.25
    write_index(tmp_path)
    assert "7.2" not in (tmp_path / "index.md").read_text()


def test_run_dependent_tables_go_to_run_md_and_a_rerun_leaves_the_summary_as_it_was(tmp_path):
    res = synthetic()
    res.tables.append(Table("timings", "CPU times", ("solve", "CPU (s)"), [("a", 0.25)], volatile=True))
    res.wall_time = 1.0
    folder = write_study(res, tmp_path)
    first = {name: (folder / name).read_bytes() for name in ("summary.md", "results.json", "numbers.csv")}
    assert "CPU times" not in first["summary.md"].decode() and b"timings" not in first["results.json"]
    assert "CPU times" in (folder / "run.md").read_text() and (folder / "run_timings.csv").is_file()
    assert json.loads((folder / "run.json").read_text())["tables"][0]["name"] == "timings"
    res.wall_time = 2.0
    write_study(res, tmp_path)
    assert all((folder / name).read_bytes() == text for name, text in first.items())
    assert "Wall time 2.0 s" in (folder / "run.md").read_text()


def test_every_run_dependent_file_starts_with_run_and_a_rerun_changes_no_other(tmp_path):
    """Volatile tables and figures, and run findings, go to run.md, run.json, run_*.csv and run_*.png only: a rerun
    with other timings leaves every other file byte for byte (reports/ ignores run* in version control)."""
    def result(cpu):
        res = synthetic()
        res.tables.append(Table("timings", "CPU times", ("solve", "CPU (s)"), [("a", cpu)], volatile=True))
        res.figures.append(Figure("speed", "CPU time", (Panel("p", "n", "CPU time (s)", (Line("a", (1, 2), (cpu, 2 * cpu)),)),),
                                  volatile=True))
        res.run_findings.append(f"the solve took {cpu:g} s")
        res.wall_time = cpu
        return res

    folder = write_study(result(0.3137), tmp_path)
    first = {p.name: p.read_bytes() for p in folder.iterdir()}
    assert {"run_timings.csv", "run_speed.png"} <= set(first)
    assert "the solve took 0.3137 s" in (folder / "run.md").read_text()
    assert json.loads(first["run.json"])["findings"] == ["the solve took 0.3137 s"]
    assert b"0.3137" not in first["results.json"] and "took" not in first["summary.md"].decode()
    write_study(result(0.6271), tmp_path)
    changed = sorted(p.name for p in folder.iterdir() if p.read_bytes() != first.get(p.name))
    assert changed and all(name.startswith("run") for name in changed)


def test_nothing_is_written_half_way(tmp_path):
    res = synthetic()
    write_study(res, tmp_path)
    res.figures.append(Figure("broken", "a figure that cannot be drawn", ("not a panel",)))
    res.checks.clear()
    with pytest.raises(AttributeError):
        write_study(res, tmp_path)
    # the previous complete folder is untouched and no temporary folder is left behind
    assert (tmp_path / "demo" / "summary.md").read_text().rstrip().endswith("2 checks passed, 1 failed")
    assert [p.name for p in tmp_path.iterdir()] == ["demo"]


def test_the_index_lists_studies_in_the_order_given(tmp_path):
    for name in ("b", "a", "c"):
        res = synthetic()
        res.study = name
        write_study(res, tmp_path)
    (tmp_path / "not-a-study").mkdir()
    index = write_index(tmp_path, order=("c", "b")).read_text()
    assert index.index("[c]") < index.index("[b]") < index.index("[a]") and "not-a-study" not in index
    assert "6 checks passed, 3 failed" in index


def test_markdown_cells_are_rounded_and_escaped():
    table = markdown_table(("x", "y"), [(0.000123456, "a | b"), (float("nan"), 3)])
    assert table.splitlines() == ["| x | y |", "|---|---|", "| 1.23e-04 | a \\| b |", "|  | 3 |"]


def test_an_unwritable_folder_is_a_value_error(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(ValueError, match="cannot write to output folder"):
        writable_folder(blocker / "sub")
    assert writable_folder(tmp_path / "new" / "sub").is_dir()


@pytest.mark.parametrize("x, decades", [((0.0156, 0.03125, 0.0625), 0), ((0.05, 0.1, 0.2), 1), ((1e-3, 1e-2, 1e-1), 3)])
def test_every_log_axis_of_a_report_figure_has_at_least_two_tick_labels(x, decades, tmp_path, monkeypatch):
    import matplotlib.pyplot as plt

    from validation.harness.report import decades_within, plot

    assert decades_within(min(x), max(x)) == decades
    drawn = []
    close = plt.close
    monkeypatch.setattr(plt, "close", lambda f=None: (drawn.append(f), close(f)))
    fig = Figure("f", "c", (Panel("t", "h (m)", "error (1)", (Line("e", x, [v**2 for v in x]),), (2.0,)),))
    plot(fig, tmp_path / "f.png")
    assert (tmp_path / "f.png").stat().st_size > 0 and len(drawn) == 1
    drawn[0].canvas.draw()
    ax = drawn[0].axes[0]
    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        shown = [t for t in axis.get_majorticklabels() + axis.get_minorticklabels()
                 if t.get_text() and lo <= t.get_position()[axis is ax.yaxis] <= hi]
        assert len(shown) >= 2, [t.get_text() for t in shown]
