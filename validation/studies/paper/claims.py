r"""A claim of the paper, what was measured of it, and its verdict, computed from the measurements.

The verdict of a :class:`Claim` is never written by hand: ``literal`` says
whether the paper's statement, as written, holds on the measured runs; the
claim's checks (the study's stated expectations, PASS/FAIL in the report)
must all pass for any verdict to be given; a claim without checks has none.

A claim that fails for any case it states is *false*, whatever else holds; its
``holds_when`` names the narrower condition under which the measurements show
it true ("false as stated; holds only ..."). A case the claim states but no
run measured (a run that diverged before its analysis window, say) is neither
a pass nor a failure: ``not_judged`` names it, and the verdict says the claim
holds only where it was measured ("holds where measured (...); not judged
..."). A claim the code cannot judge at all has ``literal=None`` and the
verdict says why (by default: pictures, to be judged by eye).
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
    literal : bool or None
        The claim, as the paper states it, holds on the measurements, for every case it states; None when no
        measurement can judge it (pictures).
    checks : tuple of bool
        The outcomes of the study's checks of this claim (:func:`checks_of`).
    holds_when : str
        When the literal claim is false: the condition under which the measurements (and the checks) show it
        true, phrased to follow "holds only ..."; when it holds but ``not_judged`` is given: where it was
        measured, phrased to follow "holds where measured".
    not_judged : str
        The cases the claim states that no measurement judged, and why, phrased to follow "not judged ...";
        with ``literal=None``: why nothing could be judged.
    """

    statement: str
    section: str
    measured: str
    literal: bool | None
    checks: tuple = ()
    holds_when: str = ""
    not_judged: str = ""

    @property
    def verdict(self) -> str:
        if not self.checks:
            return "not measured (no check)"
        if not all(self.checks):
            return f"not shown ({sum(not c for c in self.checks)} of {len(self.checks)} checks failed)"
        if self.literal is None:
            return f"not judged: {self.not_judged or 'pictures only, to be judged by eye'}"
        rest = f"; not judged {self.not_judged}" if self.not_judged else ""
        if self.literal:
            if not rest:
                return "holds"
            return f"holds where measured{f' ({self.holds_when})' if self.holds_when else ''}{rest}"
        return (f"false as stated; holds only {self.holds_when}" if self.holds_when else "false") + rest

    def row(self) -> tuple:
        return (self.statement, self.section, self.measured, self.verdict)


def checks_of(res, prefix: str) -> tuple:
    """The pass/fail outcomes of the result's checks whose name starts with ``prefix``."""
    return tuple(c.passed for c in res.checks if c.name.startswith(prefix))
