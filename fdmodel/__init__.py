"""fdmodel: the paper's finite-difference discretisation (section 2.3, TPBF87 appendix)."""

from .model import WEIGHTINGS, FDModel
from .operators import node_derivatives, operators

__all__ = ["FDModel", "WEIGHTINGS", "node_derivatives", "operators"]
