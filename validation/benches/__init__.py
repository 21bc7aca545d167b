"""The benches of ``deformable bench``, one module each (as the studies are), and how they measure.

- :mod:`.semi_implicit`: the paper's step (eq. 22-27) against its factorisation and solve;
- :mod:`.implicit`: a Newton step of the energy-consistent model against its floor (the kernels and one
  factor+solve, timed in the same process);
- :mod:`.selfcontact`: the shipped curtain with its self-contact against without;
- :mod:`.bar`: the curtain in fixed-matrix factor+solves per simulated second, with its Newton error;
- :mod:`.realtime`: the view's frames off screen, simulated over CPU seconds;
- :mod:`.scenes`: shipped scenes for seconds of motion (opt-in);
- :mod:`.rates`: simulated seconds per CPU second of the shipped scenes, with their Newton and time errors (opt-in);
- :mod:`.peers`: newton's VBD and Style3D on the hanging cloth at their example budgets (opt-in);
- :mod:`.accuracy`: the same three solvers at matched accuracy, each swept against its own most converged run;
- :mod:`.contact`: the sphere scene's step with its ball against without;
- :mod:`.measure`: an own process for each row (its peak memory), best-of timings, rows to markdown and CSV.

Each row is a frozen dataclass measured in a forked process of its own. The command
(:mod:`validation.commands.bench`) parses the arguments and runs them.
"""

from .contact import ContactRow, bench_contact, format_contact
from .implicit import ImplicitRow, bench_implicit, format_implicit
from .scenes import SceneRow, bench_scene, format_scenes
from .semi_implicit import SEMI_IMPLICIT_DT, BenchRow, bench_one, format_table, hanging_model

__all__ = ["BenchRow", "ImplicitRow", "SceneRow", "ContactRow", "bench_one", "bench_implicit", "bench_scene",
           "bench_contact", "format_table", "format_implicit", "format_scenes", "format_contact",
           "SEMI_IMPLICIT_DT", "hanging_model"]
