"""The validation studies; importing this package registers each in :data:`validation.study.STUDIES`.

Order of registration is the order ``deformable validate`` runs them.
"""

from . import tensors  # noqa: F401
from . import modes  # noqa: F401,E402
from . import statics  # noqa: F401,E402
from . import cross  # noqa: F401,E402
from . import temporal  # noqa: F401,E402  (the study "time")
from . import compatibility  # noqa: F401,E402
from . import work  # noqa: F401,E402
from . import variational  # noqa: F401,E402
from . import paper  # noqa: F401,E402
