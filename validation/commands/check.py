r"""``deformable check SCENE|FILE.toml [KEY=VALUE ...] [--grid MxN] [--rtol R] [--show-config]``: is the scene's rest
state a surface? (``--show-config``: print the config's fields instead, as ``deformable run --show-config``.)

The paper's compatibility test (section 3.2, eq. (10);
:func:`deformable.check_rest_state`) on the scene's rest metric G0 and
curvature B0: the rest shape's, the scene file's ``rest_metric`` and
``rest_curvature`` override, or a named ``rest_shape`` (a sphere, a cylinder,
a saddle, a height field: :mod:`deformable.scenes.rest_shapes`), with
KEY=VALUE overrides as ``run`` takes them (``rest_shape={kind="sphere",
radius=2}``). At every point it compares (r_11)_2 with (r_12)_1 and (r_22)_1
with (r_12)_2, computed from G0 and B0 alone, by the ratio of their
magnitudes and the cosine of their angle (both within ``rtol`` of one);
where a compared vector vanishes (a plane, a cylinder) the ratio and the
cosine are undefined and the residual |u - v| is the test instead.

Prints the verdict and the numbers behind it; exit code 0 when compatible,
1 when not, or when the test is not computable (a residual infinite or NaN:
rest tensors whose products leave double precision,
:attr:`deformable.geometry.compatibility.Compatibility.finite`), 2 on bad
input (one line on stderr).
"""

from __future__ import annotations

import math
import warnings

from deformable.errors import IncompatibleRestState, InputError
from deformable.geometry.compatibility import check_rest_state
from deformable.scenes import build

from .run import parse_grid, parse_overrides, print_config, scene_config, show_config_option

__all__ = ["configure", "execute"]


def configure(parser) -> None:
    parser.add_argument("scene", metavar="SCENE|FILE.toml", help="a scene name or a TOML scene file")
    parser.add_argument("overrides", metavar="KEY=VALUE", nargs="*", default=[],
                        help="set a field of the scene's config, e.g. rest_curvature=[2,0] or "
                        "'rest_shape={kind=\"sphere\", radius=2}' (values are TOML; default: none)")
    parser.add_argument("--grid", default=None, metavar="MxN",
                        help="points of the test (default: the scene's grid, at least 33 a side)")
    parser.add_argument("--rtol", default="0.05", help="tolerance of ratio, cosine and residual (default: 0.05)")
    show_config_option(parser)


def execute(args) -> int:
    """``deformable check``: 0 when the rest state is compatible, 1 when it is not."""
    try:
        rtol = float(args.rtol)
    except ValueError:
        raise InputError(f"--rtol must be a number in (0, 1), got {args.rtol!r}") from None
    if not (math.isfinite(rtol) and 0 < rtol < 1):
        raise InputError(f"--rtol must be a number in (0, 1), got {args.rtol!r}")
    cfg = scene_config(args.scene, **parse_overrides(args.overrides))
    if getattr(args, "show_config", False):
        return print_config(cfg)
    with warnings.catch_warnings():  # the Scene warns of an incompatible rest state; the command reports it
        warnings.simplefilter("ignore", IncompatibleRestState)
        scene = build(cfg)
    nodes = parse_grid(args.grid) if args.grid is not None else None
    if nodes is not None and min(nodes) < 9:
        raise InputError(f"grid {args.grid!r}: the test needs at least 9 points a side")
    result = check_rest_state(scene, nodes, rtol=rtol)
    grid = nodes or tuple(max(n, 33) for n in scene.sheet.nodes)
    verdict = ("compatible" if result.compatible else "NOT compatible" if result.finite else
               "NOT testable: residuals that are not finite (the rest tensors leave double precision)")
    print(f"{cfg.scene}: rest state {verdict} (the paper's test of eq. (10) on {grid[0]}x{grid[1]} points, "
          f"tolerance {rtol:g})")
    for name, c in result.comparisons.items():
        print(f"  {name}: {'pass' if c.passed else 'FAIL' if result.finite else 'not computable'}: {c.describe()}")
    print(f"  Gauss equation residual {result.gauss:.3g} 1/m^2, Mainardi-Codazzi residuals {result.codazzi[0]:.3g}, "
          f"{result.codazzi[1]:.3g}")
    return 0 if result.compatible else 1  # (not compatible where not finite)
