"""Sparse linear algebra on fixed patterns: patterns built once and refilled, element assembly, direct solvers.

- :mod:`.patterns`: a CSR pattern of contributions, coordinate-blocked patterns;
- :mod:`.elements`: element matrices of symmetric operators summed on a pattern (compiled scatter);
- :mod:`.reduced`: the free and held blocks of a Newton or step matrix, by gathers;
- :mod:`.solvers`: SuperLU and MKL PARDISO behind one interface, BLAS threads.

Imports only the ground floor.
"""

from .elements import SymmetricElements, element_vectors, scatter_upper
from .patterns import BlockPattern, FixedPattern, canonical, coordinates, same_pattern
from .reduced import ReducedSystem
from .solvers import SOLVERS, SPLU_OPTIONS, Auto, Pardiso, SuperLU, available, make_solver

__all__ = ["FixedPattern", "BlockPattern", "canonical", "same_pattern", "coordinates", "SymmetricElements",
           "element_vectors", "scatter_upper", "ReducedSystem", "SuperLU", "Pardiso", "Auto", "make_solver", "SOLVERS",
           "available", "SPLU_OPTIONS"]
