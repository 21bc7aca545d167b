r"""``deformable fabrics [NAME ...]``: the named fabrics, one line each.

The presets of :meth:`deformable.Fabric.preset` (:mod:`deformable.physics.fabric_presets`, where each value's
source and reading are stated): the name, the areal density (g/m^2), the tensile stiffness T (N/m), the bending
rigidity D (micro N m) and Peirce's bending length c = (D / (w g))^(1/3) (cm), each along the warp and the weft,
and the source in a few words. ``NAME ...`` lists those only; an unknown name ends in one line naming the
known ones (exit code 2). ``deformable validate fabrics`` measures each c by the cantilever test.
"""

from __future__ import annotations

from deformable.physics.fabric import Fabric
from deformable.physics.fabric_presets import lookup

__all__ = ["COLUMNS", "configure", "execute", "rows", "table"]

#: the table's header
COLUMNS = ("name", "density (g/m^2)", "T warp / weft (N/m)", "D warp / weft (micro N m)", "c warp / weft (cm)",
           "source")


def configure(parser) -> None:
    parser.add_argument("names", metavar="NAME", nargs="*", default=[],
                        help=f"presets to list (default: all): {', '.join(Fabric.presets())}")


def _num(v: float) -> str:
    """Three significant digits, without an exponent."""
    return f"{v:.0f}" if abs(v) >= 1000 else f"{v:#.3g}".rstrip(".")


def _pair(pair, scale: float = 1.0) -> str:
    return " / ".join(_num(scale * v) for v in pair)


def rows(names=()) -> list[tuple[str, ...]]:
    """One row of :data:`COLUMNS` per preset ``names`` (default: all, sorted); InputError for an unknown name."""
    out = []
    for name in names or Fabric.presets():
        fabric = Fabric.preset(name)
        out.append((name, _num(1e3 * fabric.density), _pair(fabric.tensile), _pair(fabric.bending, 1e6),
                    " / ".join(f"{100 * c:.2f}" for c in fabric.bending_length), lookup(name).short_source))
    return out


def table(names=()) -> list[str]:
    """The lines of the table: header, rule and one line per preset, columns padded."""
    body = rows(names)
    widths = [max(len(r[k]) for r in (COLUMNS, *body)) for k in range(len(COLUMNS))]

    def line(r):
        return "  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip()

    return [line(COLUMNS), line(tuple("-" * w for w in widths)), *map(line, body)]


def execute(args) -> int:
    """``deformable fabrics``: prints the table; 0."""
    print("\n".join(table(args.names)))
    return 0
