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

The same steps once more with the sheet's self-contact on as well (the
scene's own ``Contact(self_distance=...)``, else the obstacle's activation
distance; the rows before run without it): the
cost of self-contact against obstacle contact alone (``self ratio``; the
target is at most 2 at FD 64 x 64 nodes), and where its time goes: the
self-contact's share of a step in its broad and narrow phases (collisions,
Hessians, continuous collision detection).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from deformable import scenes
from deformable.contact.points import contact_points
from deformable.contact.selfpotential import PARTS
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
    newton_self: float
    step_self: float
    self_collisions: float
    self_barrier: float
    self_hessian: float
    self_ccd: float
    peak_mb: float

    @property
    def step_ratio(self) -> float:
        """The step with contact against the step without the obstacle."""
        return self.step_contact / self.step_free

    @property
    def self_ratio(self) -> float:
        """The step with the ball and self-contact against the step with the ball alone."""
        return self.step_self / self.step_contact

    @property
    def self_seconds(self) -> dict:
        """Wall seconds of the timed steps in the self-contact's parts
        (:attr:`deformable.contact.selfpotential.SelfContactPotential.seconds`)."""
        return {k: getattr(self, f"self_{k}") for k in PARTS}

    @property
    def self_share(self) -> float:
        """The self-contact's own share of a step with it (its seconds over the timed steps' wall time)."""
        return sum(self.self_seconds.values()) / (self.steps * self.step_self)

    @property
    def iteration_ratio(self) -> float:
        """A Newton iteration with contact against one without."""
        return (self.step_contact / self.newton_contact) / (self.step_free / self.newton_free)


def bench_contact(backend: str, n: int, steps: int, solver: str = "auto") -> ContactRow:
    """Time ``steps`` steps of the sphere scene in contact, and of the same scene without its ball."""
    base = scene_config("sphere", backend, n)
    cfg = base.replace(gap=0.5 * base.contact.distance)
    own = scenes.build(cfg)  # the scene's own: the ball and the cloth's self-contact
    scene = dataclasses.replace(own, contact=dataclasses.replace(own.contact, self_distance=None))
    model = make_model(scene, backend)
    with_ball, it_ball = timed_steps(model, cfg.dt, steps, solver)
    free = make_model(dataclasses.replace(scene, obstacles=(), contact=None), backend)
    without, it_free = timed_steps(free, cfg.dt, steps, solver)
    both = make_model(dataclasses.replace(own, contact=dataclasses.replace(
        own.contact, self_distance=own.contact.self_distance or own.contact.distance)), backend)
    with_self, it_self, seconds = timed_steps(both, cfg.dt, steps, solver,
                                              probe=lambda stepper: stepper.newton.problem.contact.sheet.seconds)
    return ContactRow(backend, f"{n}x{n}", 3 * model.ndof, contact_points(model).P, steps, it_ball, it_free,
                      with_ball, without, it_self, with_self, *(seconds[k] for k in PARTS), peak_memory())


def format_contact(rows) -> str:
    """A markdown table of contact rows (times in ms)."""
    return markdown_table(
        ("backend", "grid", "unknowns", "contact points", "steps", "Newton / step, ball", "Newton / step, none",
         "step ms, ball", "step ms, none", "step ratio", "iteration ratio", "Newton / step, ball + self",
         "step ms, ball + self", "self ratio", "self-contact share", "peak MB"),
        [(r.backend, grid_label(r), r.unknowns, r.contact_points, r.steps, f"{r.newton_contact:.2f}",
          f"{r.newton_free:.2f}", f"{1e3 * r.step_contact:.1f}", f"{1e3 * r.step_free:.1f}", f"{r.step_ratio:.2f}",
          f"{r.iteration_ratio:.2f}", f"{r.newton_self:.2f}", f"{1e3 * r.step_self:.1f}", f"{r.self_ratio:.2f}",
          f"{100 * r.self_share:.0f} % (" + ", ".join(f"{k} {100 * v / (r.steps * r.step_self):.0f} %"
                                                     for k, v in r.self_seconds.items()) + ")",
          f"{r.peak_mb:.0f}") for r in rows])
