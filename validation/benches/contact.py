r"""The contact rows of ``deformable bench``: a step of the ``sphere`` scene in contact against the same step without
its ball.

The cloth starts half the barrier's activation distance above the ball (in
contact from the first step) and is stepped ``--contact-steps`` times
(default 40, 0.2 s) after one warm-up step, against the same scene and start
with the obstacle removed (a free fall): ms per step, Newton iterations per
step, ms per iteration, and the ratios. The window is long enough for the
cloth to drape: its first steps, with only the middle of the cloth on the
ball, are the cheapest (measured at FD 64 x 64: 2.40 Newton iterations a step
over the first 5, 4.55 over the first 40). Issue 14's target is a step ratio
of at most 2 at 64 x 64 FD nodes.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from deformable import scenes
from deformable.contact.points import contact_points
from validation.harness.backends import make_model
from validation.harness.report import markdown_table

from .measure import grid_label, peak_memory, scene_config, timed_steps

__all__ = ["ContactRow", "bench_contact", "format_contact"]


@dataclass(frozen=True)
class ContactRow:
    """One contact line: the sphere scene with its ball against without; times in seconds, memory in MB."""

    backend: str
    grid: str
    unknowns: int
    contact_points: int
    steps: int
    newton_contact: float
    newton_free: float
    step_contact: float
    step_free: float
    peak_mb: float

    @property
    def step_ratio(self) -> float:
        """The step with contact against the step without the obstacle."""
        return self.step_contact / self.step_free

    @property
    def iteration_ratio(self) -> float:
        """A Newton iteration with contact against one without."""
        return (self.step_contact / self.newton_contact) / (self.step_free / self.newton_free)


def bench_contact(backend: str, n: int, steps: int, solver: str = "auto") -> ContactRow:
    """Time ``steps`` steps of the sphere scene in contact, and of the same scene without its ball."""
    base = scene_config("sphere", backend, n)
    cfg = base.replace(gap=0.5 * base.contact.distance)
    scene = scenes.build(cfg)
    model = make_model(scene, backend)
    with_ball, it_ball = timed_steps(model, cfg.dt, steps, solver)
    free = make_model(dataclasses.replace(scene, obstacles=(), contact=None), backend)
    without, it_free = timed_steps(free, cfg.dt, steps, solver)
    return ContactRow(backend, f"{n}x{n}", 3 * model.ndof, contact_points(model).P, steps, it_ball, it_free,
                      with_ball, without, peak_memory())


def format_contact(rows) -> str:
    """A markdown table of contact rows (times in ms)."""
    return markdown_table(
        ("backend", "grid", "unknowns", "contact points", "steps", "Newton / step, ball", "Newton / step, none",
         "step ms, ball", "step ms, none", "step ratio", "iteration ratio", "peak MB"),
        [(r.backend, grid_label(r), r.unknowns, r.contact_points, r.steps, f"{r.newton_contact:.2f}",
          f"{r.newton_free:.2f}", f"{1e3 * r.step_contact:.1f}", f"{1e3 * r.step_free:.1f}", f"{r.step_ratio:.2f}",
          f"{r.iteration_ratio:.2f}", f"{r.peak_mb:.0f}") for r in rows])
