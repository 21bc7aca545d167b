"""validation: analytic surfaces, convergence studies, reports, and the ``deformable`` command line."""
