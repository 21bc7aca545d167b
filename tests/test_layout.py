"""The package's layout (docs/design.md, "Layout"): no import cycle, one door from above to the backends."""

import ast
import collections
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("deformable", "fdmodel", "femodel", "validation")


def modules() -> dict[str, Path]:
    """Every module of the four packages by import name."""
    out = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            name = ".".join(path.relative_to(ROOT).with_suffix("").parts)
            out[name.removesuffix(".__init__")] = path
    return out


def import_graph(everywhere: bool = False) -> dict[str, set[str]]:
    """Imports between the modules: module-level ones (or also those inside functions, ``everywhere``);
    ``from . import sub`` is an edge to the submodule."""
    mods = modules()
    graph = collections.defaultdict(set)
    for name, path in mods.items():
        package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree) if everywhere else tree.body:
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    parts = package.split(".")
                    base = ".".join(parts[:len(parts) - node.level + 1] + ([base] if base else []))
                subs = [f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in mods]
                targets = subs if len(subs) == len(node.names) else [base, *subs]
            else:
                continue
            graph[name] |= {t for t in targets if t in mods and t != name}
    return graph


def test_there_is_no_import_cycle():
    graph, state, stack, cycles = import_graph(), {}, [], []

    def visit(u):
        state[u] = "open"
        stack.append(u)
        for v in sorted(graph[u]):
            if state.get(v) == "open":
                cycle = [*stack[stack.index(v):], v]
                if not any(b.startswith(a + ".") for a, b in zip(cycle, cycle[1:])):  # a package and its own parts
                    cycles.append(" -> ".join(cycle))
            elif v not in state:
                visit(v)
        stack.pop()
        state[u] = "done"

    for m in sorted(modules()):
        if m not in state:
            visit(m)
    assert len(state) > 50 and cycles == []


def test_above_the_backends_exactly_one_module_imports_them():
    graph = import_graph(everywhere=True)  # the one door imports them lazily, inside make_model
    above = {name for name, deps in graph.items() if not name.startswith(("fdmodel", "femodel"))
             and any(d.split(".")[0] in ("fdmodel", "femodel") for d in deps)}
    assert above == {"validation.harness.backends"}
