"""The house rules of DESIGN.md's layer picture, read from the source: no import cycle among
the project's modules (counting imports inside functions and under TYPE_CHECKING), and no
module of `solvers/` or `explorer/` over 400 lines, at most 3 functions over 60 lines (issue
18), and no module outside `explorer/panels/` reaching into a panel's widgets."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("solvers", "explorer")
MAX_LINES = 400
LONG_FUNCTION = 60  # lines, signature and docstring included
MAX_LONG_FUNCTIONS = 3


def _modules() -> dict[str, Path]:
    found = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            found[".".join(parts)] = path
    return found


def _imports(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The project modules `name` imports anywhere in its file (a `from package import
    module` names the module, not the package)."""
    base = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    targets: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            wanted = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level:
                module = ".".join(base[:len(base) - node.level + 1] + ([module] if module else []))
            subs = [f"{module}.{a.name}" for a in node.names if f"{module}.{a.name}" in modules]
            wanted = subs if len(subs) == len(node.names) else [module, *subs]
        else:
            continue
        for target in wanted:
            while target and target not in modules:
                target = target.rpartition(".")[0]
            if target and target != name:
                targets.add(target)
    return targets


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import cycle of `graph` (depth-first search), or None."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            if nxt not in state and (found := visit(nxt)):
                return found
        path.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state and (found := visit(node)):
            return found
    return None


def test_the_project_has_no_import_cycle() -> None:
    modules = _modules()
    graph = {name: _imports(name, path, modules) for name, path in modules.items()}
    assert graph["solvers.mission"] >= {"solvers.refine", "solvers.cost_error"}
    cycle = _cycle(graph)
    assert cycle is None, " -> ".join(cycle or [])


def test_the_cycle_finder_finds_a_cycle() -> None:
    """The check above can fail: a two-module knot is found."""
    assert _cycle({"a": {"b"}, "b": {"a"}, "c": set()}) == ["a", "b", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None


def test_no_module_is_over_400_lines() -> None:
    long = {name: n for name, path in _modules().items()
            if (n := len(path.read_text().splitlines())) > MAX_LINES}
    assert not long, long


def test_at_most_three_functions_are_over_60_lines() -> None:
    long = [f"{path.relative_to(ROOT)}:{node.lineno} {node.name} ({length} lines)"
            for path in _modules().values()
            for node in ast.walk(ast.parse(path.read_text()))
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
            and (length := node.end_lineno - node.lineno + 1) > LONG_FUNCTION]
    assert len(long) <= MAX_LONG_FUNCTIONS, long


PANELS = ("play", "trust", "compare", "status", "side", "controls", "export", "room")


def _widget_reaches(path: Path) -> list[str]:
    """`<...>.<panel>.<widget>.value` or `.content` in `path`: a module reaching through a
    panel into one of its widgets."""
    hits = []
    for node in ast.walk(ast.parse(path.read_text())):
        if (isinstance(node, ast.Attribute) and node.attr in ("value", "content")
                and isinstance(node.value, ast.Attribute)
                and isinstance(node.value.value, ast.Attribute)
                and node.value.value.attr.lstrip("_") in PANELS):
            hits.append(f"{path.name}:{node.lineno} {ast.unparse(node)}")
    return hits


def test_only_a_panel_touches_its_widgets() -> None:
    """Issue 18: the view wrote `play.replay_text.content`, read `trust.error_colors.value`
    and four more; a panel's widgets are its own, the rest calls its methods."""
    outside = [p for p in (ROOT / "explorer").rglob("*.py") if "panels" not in p.parts]
    assert [hit for p in outside for hit in _widget_reaches(p)] == []
    assert _widget_reaches(ROOT / "tests" / "explorer" / "test_browser_polish.py")  # it sees
