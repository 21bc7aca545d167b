r"""A claim of the paper, what was measured of it, and its verdict, computed from the measurements.

The verdict of a :class:`Claim` is never written by hand: ``literal`` says
whether the paper's statement, as written, holds on the measured runs; the
claim's checks (the study's stated expectations, PASS/FAIL in the report)
must all pass for any verdict to be given; a claim without checks has none.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Claim", "checks_of"]


@dataclass(frozen=True)
class Claim:
    """One row of the claims table.

    Parameters
    ----------
    statement, section : the paper's claim and where it is made
    measured : what the runs gave, in numbers
    literal : bool
        The claim, as the paper states it, holds on the measurements.
    checks : tuple of bool
        The outcomes of the study's checks of this claim (:func:`checks_of`).
    correction : str
        What the measurements show instead, when the literal claim does not hold (verified by the checks).
    """

    statement: str
    section: str
    measured: str
    literal: bool
    checks: tuple = ()
    correction: str = ""

    @property
    def verdict(self) -> str:
        if not self.checks:
            return "not measured (no check)"
        if not all(self.checks):
            return f"not shown ({sum(not c for c in self.checks)} of {len(self.checks)} checks failed)"
        if self.literal:
            return "holds"
        return f"holds with a correction: {self.correction}" if self.correction else "does not hold"

    def row(self) -> tuple:
        return (self.statement, self.section, self.measured, self.verdict)


def checks_of(res, prefix: str) -> tuple:
    """The pass/fail outcomes of the result's checks whose name starts with ``prefix``."""
    return tuple(c.passed for c in res.checks if c.name.startswith(prefix))
