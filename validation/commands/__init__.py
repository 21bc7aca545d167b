"""The ``deformable`` command line: ``scenes``, ``run``, ``params``, ``view``, ``check``, ``validate``, ``bench``,
``sweep`` and ``fabrics``.

Each subcommand lives in its own module, which provides ``configure(parser)``
and ``execute(args) -> int``. Bad input anywhere (a ValueError raised by the
library or by a command) ends in one line on stderr and exit code 2, never a
traceback.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import re
import signal
import sys

import deformable
from deformable.errors import NumericalError

__all__ = ["main", "parse", "CommandError", "HelpFormatter"]

# subcommand -> (module, one-line help)
COMMANDS = {
    "scenes": ("validation.commands.scenes", "the scene catalogue: each scene's name and what it is"),
    "run": ("validation.commands.run", "run a scene and write an XDMF time series (ParaView)"),
    "params": ("validation.commands.params", "a scene's parameters: macro and micro groups in SI units, the stable "
               "step, the bending length against the grid"),
    "view": ("validation.commands.view", "run a scene in a window, the paper's macro and micro parameters as "
             "sliders"),
    "check": ("validation.commands.check", "check that a scene's rest state is a surface (section 3.2, eq. (10))"),
    "validate": ("validation.commands.validate", "run validation studies and write reports"),
    "bench": ("validation.commands.bench", "time the time step of each backend"),
    "sweep": ("validation.commands.sweep", "run a scene over a grid of config values; one table (and a map)"),
    "fabrics": ("validation.commands.fabrics", "the named fabrics: density, tensile, bending, bending length, source"),
}


class CommandError(Exception):
    """Bad input to a command: printed as one line, exit code 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, no usage block
        raise CommandError(f"{self.prog}: {message}")


class HelpFormatter(argparse.HelpFormatter):
    """Help that shows every option's default: "(default: X)" appended unless the text states it already."""

    def _get_help_string(self, action):
        text = action.help or ""
        if "default" in text or action.default in (None, False, argparse.SUPPRESS) or not action.option_strings:
            return text
        return f"{text} (default: %(default)s)"


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="deformable", description="Elastic sheets after Terzopoulos et al. (1987): "
                     "finite differences and finite elements, with a validation harness.", formatter_class=HelpFormatter)
    parser.add_argument("--version", action="version", version=f"deformable {deformable.__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress details (default: off)")
    parser.add_argument("-q", "--quiet", action="store_true",
                        help="print only errors and warnings: no progress bars, no summary (default: off)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, (module, help_) in COMMANDS.items():
        p = sub.add_parser(name, help=help_, description=help_, formatter_class=HelpFormatter)
        try:
            mod = importlib.import_module(module)
        except ModuleNotFoundError as err:
            if err.name != module:
                raise
            p.set_defaults(_execute=_missing(name))
            continue
        mod.configure(p)
        p.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS,
                       help="print only errors and warnings: no progress bars, no summary (default: off)")
        p.set_defaults(_execute=mod.execute)
    return parser


def _missing(name):
    def execute(args):
        raise CommandError(f"deformable {name}: not available in this version")

    return execute


def parse(parser, argv):
    """The command line's arguments; ``KEY=VALUE`` items anywhere among the options join a command's overrides
    (``deformable sweep``: its ``KEY=VALUES``).

    (argparse gives a positional list only the items before the first option; ``deformable run hanging
    --grid 8x8 eta=25`` sets eta like ``deformable run hanging eta=25 --grid 8x8``.) Anything else left
    over is refused as argparse refuses it.
    """
    args, extra = parser.parse_known_args(argv)
    if extra:
        pairs = [item for item in extra if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*=.*", item, flags=re.DOTALL)]
        dest = next((d for d in ("overrides", "values") if hasattr(args, d)), None)  # run's KEY=VALUE, sweep's
        if dest and len(pairs) == len(extra):
            setattr(args, dest, [*getattr(args, dest), *pairs])
        else:
            rest = [item for item in extra if item not in pairs] if dest else extra
            prog = f"deformable {args.command}" if getattr(args, "command", None) else "deformable"
            raise CommandError(f"{prog}: unrecognized arguments: {' '.join(rest)}")
    return args


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if hasattr(signal, "SIGXFSZ"):  # a file-size limit (ulimit -f): a failed write (EFBIG), not a crash
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    try:
        parser = build_parser()
        args = parse(parser, argv)
        logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                            format="%(levelname)s %(name)s: %(message)s")
        if args.command is None:
            parser.print_help()
            return 0
        return int(args._execute(args) or 0)
    except (CommandError, ValueError) as err:
        print(f"error: {err}" if not str(err).startswith("deformable") else str(err), file=sys.stderr)
        return 2
    except OSError as err:  # a file system failure after the checks (disk full, folder removed)
        print(f"error: {err}", file=sys.stderr)
        return 2
    except MemoryError:
        print("error: out of memory; choose a coarser grid or a shorter run", file=sys.stderr)
        return 2
    except NumericalError as err:  # a failure of the numerics outside a run (which reports it as its status)
        print(f"error: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
