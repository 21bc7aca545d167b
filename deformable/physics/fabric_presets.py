r"""Named fabrics from measured data: what each source file states, and the :class:`~deformable.physics.fabric.Fabric`
derived from it (``Fabric.preset(name)``, ``Fabric.presets()``).

The sources. Ten fabrics measured by Wang, O'Brien and Ramamoorthi (2011, "Data-driven elastic models for cloth:
modeling and measurement", ACM SIGGRAPH), as ARCSim ships them: ``materials/<file>.json`` of ARCSim, read at
github RJshra/arcsim@dde012f6fac093701f374255eedb6d619ed926c4 (identical copies in
wxhaooo/lyra@5158f74c7c92588339e19e8f86ec7f15a2a4fdf9 and
DrapeTester/ClothDrapeTester@24a980c0c78da5cc4af36c8b6e67326b96a1de8f, arcsim/Materials/; the data's origin in
ARCSim's materials/README), and ARCSim's ``materials/paper.json``, an
estimate by ARCSim's authors, not a measurement. Every number below is a value of a row of the project's table
of sources (what public sources state, read row by row with their units), kept here as the file states it
(:data:`SOURCES`); what the model takes is derived from it in code (:func:`arguments`).

Units (the sources' table, from ARCSim's code and its sibling files): areal density kg/m^2; the stretching
slots c11, c12, c22, c33 N/m (the slot paper.json fills with E h); bending N m per unit width (the slot ARCSim's
non-measured path fills with E h^3 / (12 (1 - nu^2))). The small-strain values are the file's first stretching
row and the first (zero-curvature) column of its bending rows.

The readings, one for every preset:

- *Warp.* The source does not say which material axis is the warp: here the file's u is the warp and a1,
  v the weft and a2.
- *Tensile stiffness, T = 2 c* (:data:`STRETCH_FACTOR`). ARCSim's code doubles the file's value before it
  simulates with it (dde.cpp, evaluate_stretching_sample: k = 2 c) in W = (k0 G00^2 + 2 k1 G00 G11 + k2 G11^2
  + k3 G01^2) / 2 per unit area, G the Green strain (physics.cpp, material_model), so that a pull along u
  costs k0 e^2 / 2: T_warp = k0 = 2 c11, T_weft = 2 c22. The authors' comment in paper.json reads the slot
  as E h, i.e. T = c: this module takes the code's reading, what ARCSim simulates with, for every file,
  paper's included (whose T is then twice the E h its comment states). The coupling c12 (a Poisson's
  effect, negative for three knits) has no place in eq. (13) at Poisson's ratio 0 and is left out.
- *Shear stiffness, S = c33 / 2* (:data:`SHEAR_FACTOR`). In the same energy k3 G01^2 / 2 with G01 = gamma / 2
  and k3 = 2 c33 is c33 gamma^2 / 4 = S gamma^2 / 2 (the sources' table derives the same). Paper's file
  gives one stretching value (E h): its shear is :class:`Fabric`'s default, the mean T / 2.
- *Bending, warp and weft.* ARCSim interpolates the file's three bending rows by the angle of a hinge
  (the edge the sheet folds about) to u: row 0 for a hinge along u, 1 at 45 degrees, 2 across u
  (dde.cpp, bending_stiffness: the angle of the edge's material-space vector du). A strip that bends
  along the warp (its long axis along u = a1, curvature B_11, the weight xi_11 = D_warp / 2) folds about
  hinges across u: D_warp is the 90-degree row and D_weft the 0-degree row. (The sources' table writes its
  model weights the other way round, xi_11 = D_0 / 2; its bending lengths at 0 and 90 degrees are the ones
  below, under weft and warp.) The 45-degree row is kept (:attr:`Measured.bending`) but not used: the twist
  D_12 is :class:`Fabric`'s default sqrt(D_warp D_weft). (Read as a cylindrical bend along the bias of this
  model's energy, D_45 = (D_warp + D_weft) / 4 + D_12 / 2; it would give D_12 from 0.53 (sweater) to 1.7
  (t-shirt knit) times the default.)
- *Bending length* c = (D / (w g))^(1/3) (Peirce 1930, J. Textile Inst. 21, T377; ASTM D1388), as
  :attr:`Fabric.bending_length` derives it; the sources' table derives the same at 0 and 90 degrees.

The presets (T, D and c, the bending length, warp / weft, at the readings above; the data of Wang, O'Brien and
Ramamoorthi 2011 but paper; validation/studies/fabrics.py measures c
by the cantilever test on both backends):

================  =========  =============  =============  ===========  ==================================
name              w (g/m^2)  T (N/m)        D (micro N m)  c (cm)       ARCSim materials/ file
================  =========  =============  =============  ===========  ==================================
blanket           228        303 / 490      59.8 / 117     2.99 / 3.74  pink-ribbon-brown.json
cotton-poly       220        4033 / 4070    125 / 125      3.87 / 3.87  royal-target.json (pants)
denim             324        411 / 2028     97.0 / 64.2    3.12 / 2.72  11oz-black-denim.json
jacket-knit       284        62.3 / 88.1    37.2 / 36.3    2.37 / 2.35  camel-ponte-roma.json
jacket-polyester  113        86.1 / 343     20.3 / 14.3    2.64 / 2.35  tango-red-jet-set.json
paper             100        1.0e6 / 1.0e6  400 / 400      7.42 / 7.42  paper.json (the authors' estimate)
rib-knit          276        85.7 / 130     32.2 / 46.2    2.28 / 2.58  ivory-rib-knit.json
sweater           224        25.0 / 6.54    45.6 / 59.5    2.75 / 3.00  navy-sparkle-sweat.json
swimsuit          204        95.9 / 209     51.0 / 60.2    2.94 / 3.11  white-swim-solid.json
tablecloth        128        4004 / 4055    31.3 / 51.7    2.92 / 3.45  white-dots-on-blk.json
tshirt-knit       187        33.2 / 69.0    14.3 / 23.2    1.98 / 2.33  gray-interlock.json
================  =========  =============  =============  ===========  ==================================

Caveats. The measured values are the small-strain ends of nonlinear data (the file's other rows stiffen with
strain and curvature; the model here is linear about the flat sheet, its nonlinearity that of eq. (13));
medium confidence in the factor 2 and in which axis is the warp (the sources' table); paper is an estimate.
No source with a stated unit was found for silk, a light shirting's bending or office paper's measured
bending: no preset is named after them.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import InputError

__all__ = ["SHEAR_FACTOR", "SOURCES", "STRETCH_FACTOR", "Measured", "arguments", "lookup", "names"]

#: T = STRETCH_FACTOR x the file's stretching slot (ARCSim's code: k = 2 c; module docstring)
STRETCH_FACTOR = 2.0
#: S = SHEAR_FACTOR x the file's c33 (ARCSim's W = k3 G01^2 / 2, G01 = gamma / 2, k3 = 2 c33)
SHEAR_FACTOR = 0.5

_ARCSIM = "github RJshra/arcsim@dde012f6fac093701f374255eedb6d619ed926c4"
_COPIES = ("identical copies: wxhaooo/lyra@5158f74c7c92588339e19e8f86ec7f15a2a4fdf9, "
           "DrapeTester/ClothDrapeTester@24a980c0c78da5cc4af36c8b6e67326b96a1de8f arcsim/Materials/")
_PAPER = "Wang, O'Brien, Ramamoorthi 2011, 'Data-driven elastic models for cloth: modeling and measurement'"


@dataclass(frozen=True)
class Measured:
    """What one source file states, as it states it, and where.

    Attributes
    ----------
    name : str
        The preset's short name (a command line's).
    title : str
        The long name: the file's fabric and what it is.
    file : str
        The source file (ARCSim's materials/).
    density : float
        Areal density (kg/m^2).
    stretching : (float, float)
        The file's small-strain stretching slots c11 (along u) and c22 (along v) (N/m).
    shear : float or None
        The file's c33 (N/m); None where the source gives none.
    coupling : float or None
        The file's c12 (N/m): recorded, not used (eq. (13) at Poisson's ratio 0).
    bending : (float, float, float)
        Bending stiffness (N m) about a hinge at 0, 45 and 90 degrees to u, at zero curvature.
    estimate : bool
        An estimate by the source's authors, not a measurement.
    """

    name: str
    title: str
    file: str
    density: float
    stretching: tuple[float, float]
    shear: float | None
    coupling: float | None
    bending: tuple[float, float, float]
    estimate: bool = False

    @property
    def source(self) -> str:
        """The citation: repository @ commit and path, and the paper the data is from."""
        if self.estimate:
            return (f"{_ARCSIM} materials/{self.file} (ARCSim authors' estimate, comments in the file; "
                    "not a measurement)")
        return f"{_ARCSIM} materials/{self.file} ({_COPIES}); data from {_PAPER} (ARCSim materials/README)"

    @property
    def short_source(self) -> str:
        """The source in a few words, for a table."""
        return f"ARCSim {self.file}" + (" (authors' estimate)" if self.estimate else " (Wang et al. 2011)")


def _arcsim(name, file, what, *, density, c11, c12, c22, c33, d0, d45, d90) -> Measured:
    return Measured(name, f"{file} ({what}; measured by Wang, O'Brien, Ramamoorthi 2011)", f"{file}.json", density,
                    (c11, c22), c33, c12, (d0, d45, d90))


#: preset name -> what its source states (file values, fabrics.csv's rows "read")
SOURCES: dict[str, Measured] = {m.name: m for m in (
    _arcsim("denim", "11oz-black-denim", "jeans, 99% cotton 1% spandex", density=0.324, c11=205.352, c12=10.2341,
            c22=1013.89, c33=53.3872, d0=6.41965e-05, d45=7.33846e-05, d90=9.69516e-05),
    _arcsim("cotton-poly", "royal-target", "pants, 65% cotton 35% polyester", density=0.22, c11=2016.55,
            c12=9.17051, c22=2034.98, c33=104.76, d0=0.00012541, d45=0.000107998, d90=0.00012541),
    _arcsim("tablecloth", "white-dots-on-blk", "tablecloth, 100% polyester", density=0.128, c11=2002.09,
            c12=0.345588, c22=2027.49, c33=19.189, d0=5.17138e-05, d45=4.06595e-05, d90=3.12828e-05),
    _arcsim("jacket-polyester", "tango-red-jet-set", "jacket, 100% polyester", density=0.113, c11=43.0676,
            c12=54.3733, c22=171.425, c33=14.3147, d0=1.42938e-05, d45=2.19517e-05, d90=2.03457e-05),
    _arcsim("blanket", "pink-ribbon-brown", "blanket, 100% polyester", density=0.228, c11=151.504, c12=106.028,
            c22=244.831, c33=30.2502, d0=0.00011707, d45=8.75098e-05, d90=5.97743e-05),
    _arcsim("tshirt-knit", "gray-interlock", "t-shirt knit, 60% cotton 40% polyester", density=0.187,
            c11=16.5938, c12=-14.696, c22=34.4771, c33=36.8603, d0=2.31917e-05, d45=2.475e-05, d90=1.42676e-05),
    _arcsim("jacket-knit", "camel-ponte-roma", "jacket knit, 60% polyester 40% rayon", density=0.284,
            c11=31.1462, c12=-12.8027, c22=44.0287, c33=31.8964, d0=3.63484e-05, d45=3.30133e-05,
            d90=3.71576e-05),
    _arcsim("rib-knit", "ivory-rib-knit", "underwear, 95% cotton 5% spandex", density=0.276, c11=42.871,
            c12=-0.234556, c22=65.166, c33=83.1756, d0=4.62376e-05, d45=3.00159e-05, d90=3.22439e-05),
    _arcsim("sweater", "navy-sparkle-sweat", "sweater, 96% polyester 4% spandex", density=0.224, c11=12.4863,
            c12=-19.8753, c22=3.27243, c33=17.6163, d0=5.94697e-05, d45=4.00723e-05, d90=4.5625e-05),
    _arcsim("swimsuit", "white-swim-solid", "swimsuit, 87% nylon 13% spandex", density=0.204, c11=47.9712,
            c12=6.83452, c22=104.615, c33=60.7737, d0=6.02379e-05, d45=5.88032e-05, d90=5.10188e-05),
    # paper.json: "stretching stiffness = Eh = 0.5 MN/m", "bending stiffness ~= E(h^3)/12 = 0.4 mNm", one value
    # in every slot of its rows (isotropic): c11 = c22 = E h, the bending the same about every hinge
    Measured("paper", "paper, 100 g/m^2, h = 0.1 mm (ARCSim authors' estimate, not a measurement)", "paper.json",
             0.1, (500000.0, 500000.0), None, None, (0.0004, 0.0004, 0.0004), estimate=True),
)}


def names() -> tuple[str, ...]:
    """The presets' names, sorted."""
    return tuple(sorted(SOURCES))


def lookup(name: str) -> Measured:
    """What the source of preset ``name`` states; InputError naming the known presets for any other name."""
    try:
        return SOURCES[name]
    except (KeyError, TypeError):
        raise InputError(f"fabric {name!r} is not a preset; known: {', '.join(names())}", field="fabric",
                         value=name) from None


def arguments(name: str) -> dict:
    """The keyword arguments of :class:`~deformable.physics.fabric.Fabric` for preset ``name``, derived from its
    source's values by the readings of the module docstring: density; bending (warp, weft) = (the 90-degree row,
    the 0-degree row) (N m); tensile = STRETCH_FACTOR x (c11, c22) (N/m); shear = SHEAR_FACTOR x c33 (N/m) or the
    default; name and source."""
    m = lookup(name)
    d0, _, d90 = m.bending
    return {"density": m.density, "bending": (d90, d0), "tensile": tuple(STRETCH_FACTOR * c for c in m.stretching),
            "shear": None if m.shear is None else SHEAR_FACTOR * m.shear, "name": m.title, "source": m.source}
