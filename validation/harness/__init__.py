"""The study framework: results and checks, the case runner, reports, order fits, analytic surfaces, backends.

- :mod:`.study`: StudyResult, Check, Table, Figure, Levels, Study;
- :mod:`.runner`: Runner (serial or a process pool);
- :mod:`.report`: the report writer (summary.md, results.json, CSV, PNG) and the index;
- :mod:`.orders`: observed orders of convergence;
- :mod:`.surfaces`: analytic surfaces with closed-form G and B;
- :mod:`.backends`: the one factory that turns a backend name into a model.
"""
