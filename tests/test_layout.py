"""The house's layout (docs/design.md, "The map"): no import cycle anywhere, the wings of the core in their order,
one door from above to the backends, and the rules that keep the inner walls where they are.

Every check reads the source (``ast``), function-level imports included: an import inside a function is an
arrow like any other.
"""

import ast
import collections
import functools
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("deformable", "fdmodel", "femodel", "validation")
#: the core's floors, bottom up: a module may import its own floor's and the floors below, never above
FLOORS = (
    ("deformable.errors",),
    ("deformable.checks", "deformable.registry", "deformable.limits", "deformable.tomlio", "deformable.progress"),
    ("deformable.geometry",),
    ("deformable.algebra",),
    ("deformable.physics",),
    ("deformable.contact",),
    ("deformable.scene",),
    ("deformable.backends",),
    ("deformable.solve",),
    ("deformable.dynamics",),
    ("deformable.scenes",),
    ("deformable.io",),
    ("deformable.session",),
)


@functools.cache
def modules() -> dict[str, Path]:
    """Every module of the four packages by import name."""
    out = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            name = ".".join(path.relative_to(ROOT).with_suffix("").parts)
            out[name.removesuffix(".__init__")] = path
    return out


@functools.cache
def trees() -> dict[str, ast.Module]:
    """Every module's syntax tree (parsed once for all the checks)."""
    return {name: ast.parse(path.read_text()) for name, path in modules().items()}


def imports(name: str, tree: ast.Module, mods) -> list[tuple[str, list[str]]]:
    """(imported module, names taken) of every import of a module, wherever it stands (functions included)."""
    path = mods[name]
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(a.name, []) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([base] if base else []))
            subs = [f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in mods]
            if len(subs) == len(node.names):
                out += [(s, []) for s in subs]
            else:
                out.append((base, [a.name for a in node.names]))
    return out


@pytest.fixture(scope="module")
def graph():
    """Imports between the modules of the four packages: module -> set of modules (function-level included)."""
    mods, out = modules(), collections.defaultdict(set)
    for name, tree in trees().items():
        out[name] |= {t for t, _ in imports(name, tree, mods) if t in mods and t != name}
    return out


def floor(module: str) -> int | None:
    for k, names in enumerate(FLOORS):
        if any(module == n or module.startswith(n + ".") for n in names):
            return k
    return None


def test_there_is_no_import_cycle_anywhere(graph):
    state, stack, cycles = {}, [], []

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
    assert len(state) > 100 and cycles == []


def test_the_cores_wings_import_only_their_own_floor_and_below(graph):
    core = [m for m in modules() if m.startswith("deformable.")]
    unplaced = [m for m in core if floor(m) is None]
    assert unplaced == [], f"modules on no floor of the map: {unplaced}"
    upward = [f"{m} -> {d}" for m in core for d in sorted(graph[m]) if d.startswith("deformable.")
              and floor(d) > floor(m)]
    assert upward == []
    outside = [f"{m} -> {d}" for m in core for d in sorted(graph[m]) if not d.startswith("deformable")]
    assert outside == [], "the core imports nothing of the backends or the harness"


def test_above_the_backends_exactly_one_module_imports_them(graph):
    above = {name for name, deps in graph.items() if not name.startswith(("fdmodel", "femodel"))
             and any(d.split(".")[0] in ("fdmodel", "femodel") for d in deps)}
    assert above == {"validation.harness.backends"}
    assert not any(d.split(".")[0] == "femodel" for m, deps in graph.items() if m.startswith("fdmodel") for d in deps)
    assert not any(d.split(".")[0] == "fdmodel" for m, deps in graph.items() if m.startswith("femodel") for d in deps)


def test_newton_and_its_line_searches_import_no_contact(graph):
    for module in ("deformable.solve.newton", "deformable.solve.search"):
        assert not [d for d in graph[module] if d.startswith("deformable.contact")]


def test_no_file_in_the_core_is_over_500_lines():
    long = {name: n for name, path in modules().items() if name.startswith("deformable")
            and (n := len(path.read_text().splitlines())) > 500}
    assert long == {}


def test_the_command_line_s_run_is_argument_handling_at_most_300_lines():
    """The run itself is :class:`deformable.Simulation`'s; ``deformable run`` keeps its arguments and its lines."""
    assert len(modules()["validation.commands.run"].read_text().splitlines()) <= 300


def test_no_function_of_the_harness_is_over_80_lines():
    """A study is a set of small experiment objects, not a branch per case kind inside one long function."""
    long = [f"{name}.{node.name}: {node.end_lineno - node.lineno + 1}" for name, tree in trees().items()
            if name.startswith("validation") for node in ast.walk(tree)
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.end_lineno - node.lineno >= 80]
    assert long == []


def _builds_a_model_by_hand(tree) -> int:
    """Calls that turn a scene config into a model by hand: ``make_model(scenes.build(...), ...)`` or a model class
    called on ``scenes.build(...)``, the chain :class:`deformable.Simulation` holds once."""
    def built(node):
        return (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "build"
                and isinstance(node.func.value, ast.Name) and node.func.value.id == "scenes")

    def model(func):
        name = func.id if isinstance(func, ast.Name) else func.attr if isinstance(func, ast.Attribute) else ""
        return name == "make_model" or name.endswith("Model")

    return sum(1 for node in ast.walk(tree) if isinstance(node, ast.Call) and model(node.func) and node.args
               and built(node.args[0]))


def test_a_config_becomes_a_model_in_one_place():
    found = {name: n for name, tree in trees().items() if (n := _builds_a_model_by_hand(tree))}
    assert found == {}


def _literals(tree) -> list[str]:
    return [n.value for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, str)]


def test_the_core_names_no_backend():
    found = {name: [v for v in _literals(tree) if v in ("fd", "fe")] for name, tree in trees().items()
             if name.startswith("deformable")}
    assert {k: v for k, v in found.items() if v} == {}


def _force_model_comparisons(tree) -> int:
    """Comparisons of something called force_model with a string literal (==, !=, in / not in a tuple of them)."""
    def named(node):
        return (isinstance(node, ast.Name) and node.id == "force_model") or (
            isinstance(node, ast.Attribute) and node.attr == "force_model")

    def literal(node):
        return (isinstance(node, ast.Constant) and isinstance(node.value, str)) or (
            isinstance(node, (ast.Tuple, ast.List, ast.Set)) and node.elts and all(literal(e) for e in node.elts))

    count = 0
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            if any(named(s) for s in sides) and any(literal(s) for s in sides):
                count += 1
    return count


def test_force_models_are_asked_not_compared_with_names():
    counts = {name: n for name, tree in trees().items()
              if not name.startswith("deformable.physics.force_models") and (n := _force_model_comparisons(tree))}
    assert sum(counts.values()) <= 3, counts


def test_no_private_name_is_imported_across_modules():
    mods, found = modules(), []
    for name, tree in trees().items():
        for target, names in imports(name, tree, mods):
            found += [f"{name}: {target}.{n}" for n in names if n.startswith("_") and not n.startswith("__")]
    assert found == []


def test_every_exception_and_warning_of_the_core_is_in_the_error_module():
    errors = ast.parse((ROOT / "deformable" / "errors.py").read_text())
    known = {n.name for n in errors.body if isinstance(n, ast.ClassDef)}
    kinds = re.compile(r"(Error|Exception|Warning|Rejected|Matrix)$")
    stray = []
    for name, tree in trees().items():
        if not name.startswith("deformable") or name == "deformable.errors":
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.ClassDef):
                bases = {getattr(b, "id", getattr(b, "attr", "")) for b in node.bases}
                if bases & (known | {"Exception", "ValueError", "RuntimeError", "UserWarning", "ArithmeticError",
                                     "OSError", "Warning"}) or kinds.search(node.name):
                    stray.append(f"{name}.{node.name}")
    assert stray == [] and len(known) >= 14


def _kind_of(node) -> bool:
    """An object's kind read: ``x.kind`` (numpy's ``dtype.kind`` aside), ``getattr(x, "kind")``, a table's
    ``t["kind"]``, ``t.get("kind")`` or ``t.pop("kind")``."""
    def named(n):
        return isinstance(n, ast.Constant) and n.value == "kind"

    if isinstance(node, ast.Attribute) and node.attr == "kind":
        base = node.value
        return not ((isinstance(base, ast.Attribute) and base.attr == "dtype") or (
            isinstance(base, ast.Name) and base.id == "dtype"))
    if isinstance(node, ast.Subscript):
        return named(node.slice)
    if isinstance(node, ast.Call) and node.args:
        f = node.func
        return (isinstance(f, ast.Attribute) and f.attr in ("get", "pop") and named(node.args[0])) or (
            isinstance(f, ast.Name) and f.id == "getattr" and len(node.args) > 1 and named(node.args[1]))
    return False


def _kind_dispatch(tree) -> list[int]:
    """Lines that choose behaviour by comparing an object's kind (:func:`_kind_of`, or a name it was put in within
    the same function) with ``==`` / ``!=``, with ``in`` / ``not in`` a literal string or tuple of them, or in a
    ``match`` on string cases. Comparisons inside an f-string (building a message) are not behaviour."""
    def literal(node):
        return (isinstance(node, ast.Constant) and isinstance(node.value, str)) or (
            isinstance(node, (ast.Tuple, ast.List, ast.Set)) and node.elts and all(literal(e) for e in node.elts))

    quoted = {id(n) for s in ast.walk(tree) if isinstance(s, ast.JoinedStr) for n in ast.walk(s)}
    found = set()
    for scope in [tree] + [n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]:
        nodes = list(ast.walk(scope))
        names = set() if scope is tree else {
            t.id for n in nodes if isinstance(n, (ast.Assign, ast.AnnAssign, ast.NamedExpr)) and n.value is not None
            and any(_kind_of(v) for v in ast.walk(n.value))
            for t in (n.targets if isinstance(n, ast.Assign) else [n.target]) if isinstance(t, ast.Name)}

        def kind(node):
            return _kind_of(node) or (isinstance(node, ast.Name) and node.id in names)

        for node in nodes:
            if isinstance(node, ast.Compare) and id(node) not in quoted:
                sides = [node.left, *node.comparators]
                for op, a, b in zip(node.ops, sides, sides[1:]):
                    if isinstance(op, (ast.Eq, ast.NotEq)) and (kind(a) or kind(b)) or isinstance(
                            op, (ast.In, ast.NotIn)) and kind(a) and literal(b):
                        found.add(node.lineno)
            elif isinstance(node, ast.Match) and kind(node.subject) and any(
                    isinstance(c.pattern, ast.MatchValue) and literal(c.pattern.value) for c in node.cases):
                found.add(node.lineno)
    return sorted(found)


def test_the_core_asks_objects_rather_than_comparing_their_kinds():
    """Loads, obstacles, rest shapes and force models are asked (a method, a registry lookup), never dispatched on a
    kind string: a new load or shape is one class, not one more branch (issue 46)."""
    found = {name: lines for name, tree in trees().items() if name.startswith("deformable")
             and (lines := _kind_dispatch(tree))}
    assert found == {}
