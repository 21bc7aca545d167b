r"""The report writer: one folder per study, and an index.

For a :class:`~validation.harness.study.StudyResult` ``res`` and an output folder OUT,
:func:`write_study` writes ``OUT/<study>/``:

- ``summary.md``: description, configuration, the checks as PASS/FAIL against
  their stated expectations, the tables, the findings, the figures, and the
  closing line "N checks passed, M failed";
- ``results.json``: every number (tables, checks, data) and the resolved
  configuration;
- ``run.md`` and ``run.json``: what depends on the run rather than on the code
  (the wall time; the environment, :func:`environment`: package versions from
  importlib.metadata, the BLAS and OpenMP libraries from threadpoolctl, the
  git commit; the time of writing; the study's ``volatile`` tables and
  figures and its ``run_findings``, e.g. CPU timings), so that running a
  study again with the same code leaves summary.md, results.json, the CSVs
  and the PNGs as they were;
- ``<table>.csv`` for every table (full precision);
- ``<figure>.png`` for every figure: log-log axes with labelled axes and
  units, a legend and dashed reference-slope lines (~50-100 KB each);
- the volatile ones as ``run_<table>.csv`` and ``run_<figure>.png``: every
  run-dependent file starts with ``run``, so that one ignore pattern keeps
  them out of version control (the repository's .gitignore does, for
  reports/).

Nothing is written half-way: the folder is built under a temporary name next
to its destination and renamed into place only when complete.
:func:`write_index` writes ``OUT/index.md`` linking every study folder found
in OUT, with its pass/fail counts (the wall times are in each folder's run.md).
"""

from __future__ import annotations

import csv
import io
import json
import logging
import math
import os
import platform
import shutil
import subprocess
import tempfile
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_info

from deformable.checks import DISTRIBUTION

from .study import Figure, StudyResult, Table

__all__ = ["write_study", "write_index", "versions", "thread_pools", "git_commit", "environment", "markdown_table",
           "csv_text", "plot"]

log = logging.getLogger(__name__)
#: the distributions whose versions run.md states (beside Python's, the thread pools' and the commit)
PACKAGES = (DISTRIBUTION, "numpy", "scipy", "scikit-fem", "numba", "ipctk", "pypardiso", "matplotlib", "meshio", "h5py")


def writable_folder(path) -> Path:
    """Create ``path`` if needed and check that files can be written in it; ValueError otherwise.

    Called before any work starts, so a bad ``--out`` costs nothing and leaves nothing half-written.
    """
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path, prefix=".write-test-"):
            pass
    except OSError as err:
        raise ValueError(f"cannot write to output folder {str(path)!r}: {err.strerror or err}") from None
    return path


def versions() -> dict[str, str]:
    """Versions of Python and of the distributions of :data:`PACKAGES` (importlib.metadata; "not installed" for one
    that is not)."""
    out = {"python": platform.python_version()}
    for p in PACKAGES:
        try:
            out[p] = metadata.version(p)
        except metadata.PackageNotFoundError:
            out[p] = "not installed"
    return out


def thread_pools() -> list[dict]:
    """The BLAS and OpenMP libraries loaded in this process, as threadpoolctl reports them: each one's user_api
    ("blas", "openmp"), internal_api ("openblas", "mkl", ...), version and num_threads."""
    keys = ("user_api", "internal_api", "version", "num_threads")
    return [{k: info.get(k) for k in keys} for info in threadpool_info()]


def git_commit(cwd=None) -> str:
    """The commit checked out in ``cwd`` (default: the working directory), "not a git checkout" when it is not one
    or git cannot say (no git, a timeout): never an error."""
    try:
        done = subprocess.run(["git", "rev-parse", "HEAD"], cwd=cwd, capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return "not a git checkout"
    commit = done.stdout.strip()
    return commit if done.returncode == 0 and commit else "not a git checkout"


def environment() -> dict:
    """What a run's results may depend on besides the code: :func:`versions`, :func:`thread_pools` and the
    :func:`git_commit` of the working directory (run.md and run.json)."""
    return {"versions": versions(), "thread_pools": thread_pools(), "git_commit": git_commit()}


def _environment_page(env: dict) -> list[str]:
    """run.md's "Environment" section: the versions, the thread pools and the commit."""
    rows = [*env["versions"].items(), ("git commit", env["git_commit"])]
    out = ["## Environment", "", markdown_table(("package", "version"), rows), ""]
    if env["thread_pools"]:
        pools = [(p["user_api"], p["internal_api"], p["version"], p["num_threads"]) for p in env["thread_pools"]]
        out += [markdown_table(("thread pool", "library", "version", "threads"), pools), ""]
    else:
        out += ["No BLAS or OpenMP library loaded (threadpoolctl found none).", ""]
    return out


def _json_default(obj):
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (np.floating, np.integer, np.bool_)):
        return obj.item()
    if isinstance(obj, (tuple, set)):
        return list(obj)
    return str(obj)


def _clean(obj):
    """NaN and infinities as None (strict JSON), recursively."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, (np.floating,)):
        return _clean(float(obj))
    if isinstance(obj, (np.integer, np.bool_)):
        return obj.item()
    return obj


def _cell(v) -> str:
    """A table cell for markdown: numbers rounded to 3 significant digits, NaN blank."""
    if isinstance(v, (bool, np.bool_)):
        return str(bool(v))
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        if not math.isfinite(v):
            return ""
        if v == 0:
            return "0"
        return f"{v:.3g}" if 1e-3 <= abs(v) < 1e4 else f"{v:.2e}"
    return str(v).replace("|", "\\|")


def markdown_table(columns, rows) -> str:
    """A GitHub-flavoured markdown table."""
    lines = ["| " + " | ".join(_cell(c) for c in columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(_cell(v) for v in r) + " |" for r in rows]
    return "\n".join(lines)


def _csv_value(v):
    """A CSV cell: numbers as plain numerals in full precision (shortest round-trip), NaN and inf empty."""
    if isinstance(v, (bool, np.bool_)):
        return str(bool(v))
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return repr(float(v)) if math.isfinite(v) else ""
    return v


def csv_text(table: Table) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(table.columns)
    for r in table.rows:
        w.writerow([_csv_value(v) for v in r])
    return buf.getvalue()


def decades_within(lo: float, hi: float) -> int:
    """How many powers of ten [lo, hi] (positive) holds: a log axis over it has that many decade labels."""
    return max(0, math.floor(math.log10(hi)) - math.ceil(math.log10(lo)) + 1)


def _minor_labels(mantissas):
    """A tick formatter labelling the minor ticks m x 10^e of a log axis whose mantissa m is in ``mantissas``."""
    from matplotlib.ticker import FuncFormatter

    def label(v, _pos):
        e = math.floor(math.log10(v) + 1e-9)
        m = round(v / 10**e, 6)
        return f"${m:g}\\times10^{{{e}}}$" if any(abs(m - k) < 1e-6 for k in mantissas) else ""

    return FuncFormatter(label)


def plot(fig: Figure, path: Path) -> None:
    """Draw ``fig`` as a PNG: log-log panels, markers, legend, dashed reference slopes; an axis spanning less than
    two decades labels some minor ticks too (2, 3, 5 x 10^k with no decade inside, 2, 5 x 10^k with one), so every
    axis has at least two labels."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    n = len(fig.panels)
    crowded = max(len(p.lines) + len(p.slopes) for p in fig.panels) > 6  # legend below the axes
    f, axes = plt.subplots(1, n, figsize=(5.2 * n, 5.4 if crowded else 4.2), dpi=90, squeeze=False)
    for ax, panel in zip(axes[0], fig.panels):
        xs, ys = [], []
        for line in panel.lines:
            x, y = np.asarray(line.x), np.asarray(line.y)
            ok = (x > 0) & (y > 0) & np.isfinite(y)
            if ok.sum() == 0:
                continue
            ax.loglog(x[ok], y[ok], line.style, label=line.label, ms=4, lw=1.3)
            xs.append(x[ok])
            ys.append(y[ok])
        if xs and panel.slopes:
            x_all, y_all = np.concatenate(xs), np.concatenate(ys)
            x0, x1 = x_all.min(), x_all.max()
            # anchor each reference line at the right end, a little below the geometric mean of the data there
            y_anchor = np.exp(np.mean(np.log(y_all))) * 0.3
            xr = np.array([x0, x1])
            for p, style in zip(panel.slopes, ("--", ":", "-.", (0, (5, 1, 1, 1)))):
                yr = y_anchor * (xr / x1) ** p
                ax.loglog(xr, yr, linestyle=style, color="0.35", lw=1.2,
                          label=f"reference O({panel.slope_label}^{p:g})")
        ax.set_xlabel(panel.xlabel)
        ax.set_ylabel(panel.ylabel)
        ax.set_title(panel.title, fontsize=10)
        ax.grid(True, which="major", alpha=0.3)
        for axis, lim in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
            decades = decades_within(*lim)  # 0: no label without the minor ones; 1: one label
            if decades < 2:  # label some minor ticks too, so every axis has at least two labels
                axis.set_minor_formatter(_minor_labels((2, 3, 5) if decades == 0 else (2, 5)))
                axis.set_tick_params(which="minor", labelsize=8)
            else:
                axis.set_minor_formatter(NullFormatter())
        if panel.lines and crowded:
            ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
        elif panel.lines:
            ax.legend(fontsize=7, loc="best", framealpha=0.8)
    f.tight_layout()
    f.savefig(path, dpi=90)
    plt.close(f)


def _tables(tables) -> list[str]:
    out = []
    for t in tables:
        out += [f"## {t.title}", ""]
        if t.note:
            out += [t.note, ""]
        out += [markdown_table(t.columns, t.rows), "", f"(CSV: [{_file(t)}.csv]({_file(t)}.csv))", ""]
    return out


def _file(item) -> str:
    """The file stem of a table or figure: ``run_<name>`` for a volatile one (module docstring)."""
    return f"run_{item.name}" if item.volatile else item.name


def _figures(figures) -> list[str]:
    out = ["## Figures", ""] if figures else []
    for fig in figures:
        out += [f"![{fig.caption}]({_file(fig)}.png)", "", f"*{fig.caption}*", ""]
    return out


def _summary(res: StudyResult) -> str:
    out = [f"# Study `{res.study}`", "", res.description, ""]
    out += ["## Configuration", "", "```json", json.dumps(_clean(res.config), indent=1, default=_json_default), "```",
            "", "Wall time, package versions and run-dependent measurements: [run.md](run.md).", ""]
    out += ["## Checks", ""]
    if res.checks:
        out.append(markdown_table(("result", "check", "expectation", "observed"),
                                  [("PASS" if c.passed else "**FAIL**", c.name, c.expectation, c.observed)
                                   for c in res.checks]))
    else:
        out.append("No checks.")
    out.append("")
    out += _tables([t for t in res.tables if not t.volatile])
    if res.findings:
        out += ["## Findings", ""] + [f"- {f}" for f in res.findings] + [""]
    out += _figures([f for f in res.figures if not f.volatile])
    out.append(f"{res.passed} checks passed, {res.failed} failed")
    return "\n".join(out) + "\n"


def _run_page(res: StudyResult, env: dict) -> str:
    out = [f"# Study `{res.study}`: this run", "", f"Wall time {res.wall_time:.1f} s.", ""]
    out += _tables([t for t in res.tables if t.volatile])
    if res.run_findings:
        out += ["## Findings of this run", ""] + [f"- {f}" for f in res.run_findings] + [""]
    out += _figures([f for f in res.figures if f.volatile])
    out += _environment_page(env)
    return "\n".join(out) + "\n"


def write_study(res: StudyResult, out: str | os.PathLike) -> Path:
    """Write ``out/<study>/`` for one finished study (atomically); returns the folder."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    final = out / res.study
    tmp = Path(tempfile.mkdtemp(prefix=f".{res.study}-", dir=out))
    try:
        env = environment()
        (tmp / "summary.md").write_text(_summary(res))
        (tmp / "run.md").write_text(_run_page(res, env))
        payload = res.to_dict()
        volatile = {t.name for t in res.tables if t.volatile}
        run = {"wall_time": res.wall_time, **env,
               "written": datetime.now(timezone.utc).isoformat(timespec="seconds"),
               "tables": [t for t in payload["tables"] if t["name"] in volatile], "findings": list(res.run_findings)}
        payload["tables"] = [t for t in payload["tables"] if t["name"] not in volatile]
        (tmp / "results.json").write_text(json.dumps(_clean(payload), indent=1, default=_json_default))
        (tmp / "run.json").write_text(json.dumps(_clean(run), indent=1, default=_json_default))
        for t in res.tables:
            (tmp / f"{_file(t)}.csv").write_text(csv_text(t))
        for fig in res.figures:
            if fig.image is not None:  # drawn by the study itself
                (tmp / f"{_file(fig)}.png").write_bytes(fig.image)
            else:
                plot(fig, tmp / f"{_file(fig)}.png")
        os.chmod(tmp, 0o755)
        if final.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{res.study}-old-", dir=out))
            os.replace(final, old / res.study)
            os.replace(tmp, final)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, final)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    log.info("wrote %s (%d checks passed, %d failed)", final, res.passed, res.failed)
    return final


def write_index(out: str | os.PathLike, order=()) -> Path:
    """Write ``out/index.md`` linking every study folder in ``out`` that has a results.json.

    ``order``: study names in the order to list them (others follow by name).
    """
    out = Path(out)
    order = {name: k for k, name in enumerate(order)}
    rows = []
    folders = [p for p in out.iterdir() if p.is_dir() and not p.name.startswith(".")]
    for d in sorted(folders, key=lambda p: (order.get(p.name, len(order)), p.name)):
        f = d / "results.json"
        if not f.exists():
            continue
        r = json.loads(f.read_text())
        rows.append((f"[{r['study']}]({d.name}/summary.md)", r.get("description", ""), r.get("passed", 0),
                     r.get("failed", 0), r.get("config", {}).get("levels", "")))
    passed = sum(r[2] for r in rows)
    failed = sum(r[3] for r in rows)
    text = ["# Validation reports", "",
            "Generated by `deformable validate`; each study folder holds summary.md, results.json, CSV tables "
            "and PNG plots; wall times and other run-dependent measurements are in each folder's run.md.", "",
            markdown_table(("study", "what it measures", "passed", "failed", "levels"), rows), "",
            f"{passed} checks passed, {failed} failed", ""]
    path = out / "index.md"
    path.write_text("\n".join(text))
    return path
