"""A parameter sweep: where the paper's semi-implicit step loses the hanging cloth, over eta and dt
================================================================================================

The paper's force (14) stepped by its semi-implicit scheme (eq. 22-27) lags
alpha = eta (G - G0), so the step is stable only below about
``h sqrt(mu / (2 eta G))`` (docs/design.md, "Time stepping"): the paper's
"too large eta loses equilibrium". A sweep maps it: the ``hanging`` scene
under ``force_model = "tpbf87"``, one run per (eta, dt), each row its status
(finished / diverged), the time reached and the final energy.

The sweep API (``validation.harness.sweep``) is what ``deformable sweep``
runs: a :class:`Sweep` is a base scene config (``deformable.scenes``), axes
``(key, values)`` over its fields and the backends; ``Sweep.run(runner, out)``
runs the cases through an executor (``Runner()`` serially here,
``Runner(jobs=2)`` a process pool, ``Runner(scheduler="local:4")`` Dask),
storing each case in ``out/cases/`` as it finishes, so running this script
again takes the stored cases and runs nothing; ``write_outputs`` writes
sweep.csv, sweep.md, sweep.toml and, for two swept keys, the status map
sweep.png. The same sweep on the command line::

    deformable sweep hanging force_model=tpbf87 nodes=10x10 t_end=0.3 eta=10:1000:5:log dt=1e-3,2e-3,4e-3

    python examples/sweep.py [OUT]             # OUT defaults to $EXAMPLES_OUT or examples/out/
"""

import os
import sys
from pathlib import Path

import numpy as np

from deformable import scenes
from validation.harness.runner import Runner
from validation.harness.sweep import Sweep, write_outputs

OUT = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("EXAMPLES_OUT") or Path(__file__).with_name("out"))
FINE = os.environ.get("EXAMPLES_FINE") == "1"

base = scenes.config("hanging", force_model="tpbf87", nodes=(10, 10), t_end=0.3)
axes = (("eta", tuple(float(e) for e in np.geomspace(10.0, 1000.0, 9 if FINE else 5))),
        ("dt", (1e-3, 2e-3, 4e-3)))  # dt swept: each case keeps its dt (no backend-chosen step)
sweep = Sweep(base, axes, backends=("fd",))

folder = OUT / "sweep"
with Runner() as runner:
    records, ran = sweep.run(runner, folder)
write_outputs(folder, sweep, records, command="examples/sweep.py")

h = base.size[0] / (base.nodes[0] - 1)
print(f"sweep of hanging (tpbf87, {base.nodes[0]} x {base.nodes[1]} nodes, t_end = {base.t_end:g} s): "
      f"{len(records)} cases, {ran} run now, {len(records) - ran} from {folder / 'cases'}")
print("    eta (N/m)    dt (s)   status     t reached (s)   dt / (h sqrt(mu / 2 eta))")
ratio = {"finished": [], "diverged": []}
for case, record in zip(sweep.cases(), records):
    f = dict(case.fields)
    r = f["dt"] / (h * np.sqrt(f["mu"] / (2 * f["eta"])))  # dt over the stretching bound at G = 1
    ratio.setdefault(record["status"], []).append(r)
    print(f"  {f['eta']:10.4g}   {f['dt']:7.0e}   {record['status']:9s}  {record['t']:8.3f}        {r:.2f}")
print(f"dt over the bound: finished runs up to {max(ratio['finished'], default=np.nan):.2f}, "
      f"diverged runs from {min(ratio['diverged'], default=np.nan):.2f} (stretching, G > 1, lowers the bound)")
print(f"wrote {folder / 'sweep.png'} and {folder / 'sweep.md'}")
