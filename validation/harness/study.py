r"""The study framework: result objects, checks, level sets and the :class:`Study` record.

A *study* is a :class:`Study`: a name, a description, its level counts and a
function ``fill(res, levels, runner[, surfaces])`` that builds a list of
independent cases (frozen dataclasses), maps a module-level case function over
them with ``runner.map`` (serially, or on a process pool for
``deformable validate --jobs N``, :mod:`validation.harness.runner`), and fills
the :class:`StudyResult` it is handed: tables, checks against stated
expectations, findings and figures. :meth:`Study.run` is the one entry point
(it makes the result and, when none is given, a serial runner). The report
writer (:mod:`validation.harness.report`) knows nothing else. The registry of
studies is :data:`validation.studies.STUDIES`.

Level sets. Each study declares :class:`Levels`: how many refinement levels
``--quick`` and ``--full`` run and how many it accepts at all. Level k of a
spatial study has ``(coarsest - 1) 2^k + 1`` nodes a side, so consecutive
levels halve h (refinement ratio 2, as the observed order
``p = log(e_h / e_{h/2}) / log 2`` and Roache's GCI assume).

Checks. An observed order p is *checked* against a window around the order
theory predicts (:data:`ORDER_WINDOW` around it unless a study states
otherwise), never against what the code happened to give; results whose
structure makes the generic theory inapplicable (exact, superconvergent) are
*findings* with their explanation, not checks.
"""

from __future__ import annotations

import logging
from dataclasses import asdict, dataclass, field
from typing import Callable

import numpy as np

from deformable.errors import InputError

from .runner import Runner

__all__ = ["Check", "Table", "Line", "Panel", "Figure", "StudyResult", "Levels", "Study", "ORDER_WINDOW",
           "order_check", "nodes_at"]

log = logging.getLogger(__name__)

#: default window (below, above) around the theoretical order for a checked observed order
ORDER_WINDOW = (0.3, 0.3)


@dataclass(frozen=True)
class Check:
    """One pass/fail statement: what was expected, what was observed."""

    name: str
    expectation: str
    observed: str
    passed: bool


@dataclass(frozen=True)
class Table:
    """A table of the report: written as markdown in summary.md and as ``<name>.csv``.

    ``rows`` hold numbers (written with full precision in the CSV, rounded in
    markdown) or strings. A ``volatile`` table holds what depends on the run
    (timings): it goes to run.md and ``run_<name>.csv``, so that the committed
    summary.md, results.json and CSVs do not change when a study runs again.
    """

    name: str
    title: str
    columns: tuple[str, ...]
    rows: tuple[tuple, ...]
    note: str = ""
    volatile: bool = False

    def __post_init__(self):
        object.__setattr__(self, "columns", tuple(self.columns))
        object.__setattr__(self, "rows", tuple(tuple(r) for r in self.rows))
        for r in self.rows:
            if len(r) != len(self.columns):
                raise ValueError(f"table {self.name!r}: row {r!r} has {len(r)} cells, expected {len(self.columns)}")


@dataclass(frozen=True)
class Line:
    """A plotted series: points (x, y), both positive for log-log axes."""

    label: str
    x: tuple[float, ...]
    y: tuple[float, ...]
    style: str = "o-"

    def __post_init__(self):
        object.__setattr__(self, "x", tuple(float(v) for v in self.x))
        object.__setattr__(self, "y", tuple(float(v) for v in self.y))


@dataclass(frozen=True)
class Panel:
    """One log-log axes: lines, reference slopes drawn as dashed lines, labelled axes (with units)."""

    title: str
    xlabel: str
    ylabel: str
    lines: tuple[Line, ...]
    slopes: tuple[float, ...] = ()
    slope_label: str = "h"  # reference lines are labelled "O(<slope_label>^p)"


@dataclass(frozen=True)
class Figure:
    """A PNG of the report, ``<name>.png``: one or more panels side by side.

    ``image``, when given, is a PNG the study drew itself (a render, a map):
    the report writer stores those bytes instead of plotting ``panels``. A
    ``volatile`` figure shows what depends on the run (timings): run.md and
    ``run_<name>.png``.
    """

    name: str
    caption: str
    panels: tuple[Panel, ...] = ()
    image: bytes | None = field(default=None, repr=False)
    volatile: bool = False


@dataclass
class StudyResult:
    """What a study returns; everything the report writer needs.

    Attributes
    ----------
    study, description : str
    config : dict
        The resolved configuration (levels, parameters) the study ran with.
    tables, checks, figures : lists
    findings : list of str
        Observations outside the checked theory, each with its explanation.
    run_findings : list of str
        Findings that depend on the run (timings): written to run.md and run.json, like volatile tables.
    data : dict
        All the numbers (JSON-serialisable after numpy conversion).
    """

    study: str
    description: str
    config: dict = field(default_factory=dict)
    tables: list[Table] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    findings: list[str] = field(default_factory=list)
    run_findings: list[str] = field(default_factory=list)
    data: dict = field(default_factory=dict)
    wall_time: float = 0.0

    @property
    def passed(self) -> int:
        return sum(c.passed for c in self.checks)

    @property
    def failed(self) -> int:
        return sum(not c.passed for c in self.checks)

    def check(self, name: str, expectation: str, observed: str, passed) -> bool:
        """Append a :class:`Check`; returns ``passed`` as a bool."""
        self.checks.append(Check(name, expectation, observed, bool(passed)))
        return bool(passed)

    def check_all(self, name: str, expectation: str, items: dict) -> bool:
        """A check that every item holds; over an empty set it fails (nothing was shown).

        ``items`` maps a label of each case to whether it holds; the observation lists the failures.
        """
        bad = [k for k, ok in items.items() if not ok]
        if not items:
            observed = "no case to check"
        else:
            observed = f"{len(items) - len(bad)} of {len(items)} hold" + (f"; not: {', '.join(map(str, bad))}"
                                                                          if bad else "")
        return self.check(name, expectation, observed, bool(items) and not bad)

    def to_dict(self) -> dict:
        return {
            "study": self.study, "description": self.description, "config": self.config,
            "checks": [asdict(c) for c in self.checks],
            "tables": [{"name": t.name, "title": t.title, "columns": list(t.columns), "rows": [list(r) for r in t.rows]}
                       for t in self.tables],
            "findings": list(self.findings), "data": self.data, "passed": self.passed, "failed": self.failed,
        }


def order_check(result: StudyResult, name: str, p: float, theory: float, finest: float | None = None,
                bound: float | None = None, window: tuple[float, float] = ORDER_WINDOW) -> bool:
    """Check an observed order against ``[theory - window[0], theory + window[1]]``.

    With ``finest`` and ``bound`` the finest-level error must also stay below ``bound``.
    """
    lo, hi = theory - window[0], theory + window[1]
    ok = bool(np.isfinite(p) and lo <= p <= hi)
    expectation = f"order {theory:g} (window [{lo:.2f}, {hi:.2f}])"
    observed = f"p = {p:.2f}"
    if finest is not None and bound is not None:
        ok = ok and finest <= bound
        expectation += f", finest error <= {bound:.2g}"
        observed += f", finest error {finest:.2e}"
    return result.check(name, expectation, observed, ok)


def nodes_at(level: int, coarsest: int) -> int:
    """Nodes a side at refinement level ``level`` (0 is the coarsest): (coarsest - 1) 2^level + 1."""
    return (coarsest - 1) * 2**level + 1


@dataclass(frozen=True)
class Levels:
    """Level counts of a study: ``quick`` and ``full`` defaults, and the accepted range.

    ``minimum`` is the fewest levels at which every check of the study can pass (an order window needs
    levels in the asymptotic range); fewer are refused rather than reported as a failed check.
    """

    quick: int
    full: int
    minimum: int = 3
    maximum: int = 8

    def resolve(self, study: str, mode: str = "quick", count: int | None = None) -> int:
        """The number of levels to run; ValueError naming the accepted range otherwise."""
        if count is None:
            if mode not in ("quick", "full"):
                raise InputError(f"unknown level set {mode!r}; expected 'quick' or 'full'", field="mode", value=mode)
            return self.quick if mode == "quick" else self.full
        if isinstance(count, bool) or int(count) != count or not self.minimum <= count <= self.maximum:
            raise InputError(f"study {study!r} runs {self.minimum} to {self.maximum} levels, got {count!r}",
                             field="--levels", value=count)
        return int(count)


@dataclass(frozen=True)
class Study:
    """A study: its name, what it measures, its level counts and the function that fills its result.

    ``fill(res, levels, runner)`` (and ``surfaces=`` when ``surfaces`` is true)
    adds tables, checks, findings and figures to ``res``. ``in_default`` is
    False for a study too long for the default run of ``deformable validate``
    (every study in under two minutes); it runs when named.
    """

    name: str
    description: str
    levels: Levels
    fill: Callable[..., None]
    surfaces: bool = False
    in_default: bool = True

    def run(self, levels: int | None = None, *, runner: Runner | None = None, surfaces=None,
            mode: str = "quick") -> StudyResult:
        """Run the study (``levels`` checked against its range; default: the ``mode`` level count)."""
        levels = self.levels.resolve(self.name, mode, levels)
        res = StudyResult(self.name, self.description, config={"levels": levels})
        kwargs = {"surfaces": surfaces} if self.surfaces else {}
        self.fill(res, levels, runner or Runner(), **kwargs)
        return res
