r"""``deformable params SCENE|FILE.toml [KEY=VALUE ...] [--backend fd|fe] [--grid MxN] [--show-config]``: the scene's
parameters.

The paper's two groups in SI units (:func:`deformable.scenes.parameters`): macro-control (mu, gamma, the
force f, scaled together by ``scale``) and micro-control (eta, xi), what ``scale`` did in words, the
stable step of the semi-implicit scheme for them, and the bending length against the grid spacing (the
folds resolved or not). ``deformable run`` prints the same at its start. ``--show-config`` prints every
field of the config instead, as ``deformable run --show-config`` does. Exit code 0, 2 on bad input.
"""

from __future__ import annotations

from argparse import Namespace

from deformable.scenes import parameters

from .run import backend_option, force_model_option, print_config, resolve, show_config_option

__all__ = ["configure", "execute"]


def configure(parser) -> None:
    parser.add_argument("scene", metavar="SCENE|FILE.toml", help="a scene name or a TOML scene file")
    parser.add_argument("overrides", metavar="KEY=VALUE", nargs="*", default=[],
                        help="set a field of the scene's config, e.g. scale=20 xi=1e-4 (values are TOML; default: none)")
    backend_option(parser, default_text="the scene file's, else fd")
    parser.add_argument("--grid", default=None, metavar="MxN", help="node grid MxN (default: the scene's, as run takes it)")
    force_model_option(parser, default_text="the scene's")
    show_config_option(parser)

def execute(args) -> int:
    """``deformable params``: prints the parameters; 0."""
    sim, *_ = resolve(Namespace(scene=args.scene, overrides=args.overrides, backend=args.backend,
                           grid=args.grid, force_model=args.force_model, resume=None))
    cfg, backend, model = sim.config, sim.backend, sim.model
    if getattr(args, "show_config", False):
        return print_config(cfg)
    print("\n".join(parameters(cfg, model, backend).lines()))
    return 0
