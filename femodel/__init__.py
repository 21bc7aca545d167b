"""femodel: finite elements with scikit-fem on the parameter rectangle (in progress)."""
