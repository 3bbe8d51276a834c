"""Imports run one way, down the data flow, and never in a circle.

The layers, lowest first (docs/ARCHITECTURE.md draws them): the shared mathematics and types,
the file formats, then the steps a frame goes through (shots, detection, re-initialisation,
the graph, the tracking loop), what is made of a run (metrics, the synthetic clip, products),
and the jobs a user asks for (actions, benchmarks, commands). A module may import its own
package and any lower layer, never a layer above it or beside it. Function-local imports count
as imports: a cycle hidden in a function is still a cycle.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

LAYERS = (
    ("broadtrack_graph",),
    ("broadtrack_graph.errors",),
    ("broadtrack_graph.geometry",),
    ("broadtrack_graph.types", "factors"),
    ("broadtrack_graph.io",),
    ("broadtrack_graph.shots",),
    ("broadtrack_graph.detect",),
    ("broadtrack_graph.reinit",),
    ("broadtrack_graph.graph",),
    ("broadtrack_graph.track",),
    ("broadtrack_graph.metrics", "broadtrack_graph.synth"),
    ("broadtrack_graph.products",),
    ("broadtrack_graph.actions",),
    ("broadtrack_graph.benchmarks",),
    ("broadtrack_graph.commands",),
    ("broadtrack_graph.cli",),
)
"""Packages (or top-level modules) per layer, lowest first; those on one line may not import each other."""


def module_files() -> dict[str, Path]:
    """Dotted module name -> file, for every module of the package and of ``factors``."""
    modules = {}
    for top in ("broadtrack_graph", "factors"):
        for path in sorted((ROOT / top).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            modules[".".join(parts)] = path
    return modules


def import_graph(modules: dict[str, Path]) -> dict[str, set[str]]:
    """Module -> the project modules it imports (at the top or inside a function)."""
    graph = defaultdict(set)
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join(anchor + ([node.module] if node.module else []))
                targets = [base] + [f"{base}.{alias.name}" for alias in node.names]
            elif isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            else:
                continue
            graph[name].update(t for t in targets if t in modules and t != name)
    return graph


def layer_of(module: str) -> tuple[int, str]:
    """(layer index, the layer entry the module belongs to): its longest matching entry."""
    best = None
    for index, entries in enumerate(LAYERS):
        for entry in entries:
            if module == entry or module.startswith(entry + "."):
                if best is None or len(entry) > len(best[1]):
                    best = (index, entry)
    assert best is not None, f"{module} is in no layer: add its package to LAYERS"
    return best


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    """'a -> b' for every import of a module from a higher layer, or from a sibling of the same layer."""
    bad = []
    for source, targets in sorted(graph.items()):
        source_layer, source_entry = layer_of(source)
        for target in sorted(targets):
            target_layer, target_entry = layer_of(target)
            if target_entry == source_entry:
                continue
            if target_layer >= source_layer:
                bad.append(f"{source} -> {target}")
    return bad


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import cycles: strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []
    counter = [0]

    def visit(node: str) -> None:
        index[node] = low[node] = counter[0]
        counter[0] += 1
        stack.append(node)
        on_stack.add(node)
        for nxt in graph.get(node, ()):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def test_every_module_has_a_layer():
    for module in module_files():
        layer_of(module)


def test_no_upward_or_sideways_import():
    bad = upward_imports(import_graph(module_files()))
    assert not bad, "imports against the layers (lowest first: see LAYERS):\n" + "\n".join(bad)


def test_no_import_cycle():
    found = cycles(import_graph(module_files()))
    assert not found, "import cycles:\n" + "\n".join(" <-> ".join(c) for c in found)


def test_no_module_over_400_lines():
    long = {name: n for name, path in module_files().items() if (n := len(path.read_text().splitlines())) > 400}
    assert not long, f"modules over 400 lines (split them by job): {long}"


def test_the_checks_catch_what_they_should():
    graph = {"broadtrack_graph.io.x": {"broadtrack_graph.track.y"}, "broadtrack_graph.track.y": {"broadtrack_graph.io.x"},
             "broadtrack_graph.metrics.a": {"broadtrack_graph.synth.b"}, "broadtrack_graph.track.z": {"broadtrack_graph.io.x"}}
    assert upward_imports(graph) == ["broadtrack_graph.io.x -> broadtrack_graph.track.y",
                                     "broadtrack_graph.metrics.a -> broadtrack_graph.synth.b"]
    assert cycles(graph) == [["broadtrack_graph.io.x", "broadtrack_graph.track.y"]]


NO_FILES = ("broadtrack_graph.geometry", "factors", "broadtrack_graph.metrics")
"""Mathematics and metrics work on data: they import no file format (the run folder, a camera file)."""


def test_maths_and_metrics_read_no_files():
    graph = import_graph(module_files())
    bad = [f"{source} -> {target}" for source, targets in sorted(graph.items()) for target in sorted(targets)
           if layer_of(source)[1] in NO_FILES and layer_of(target)[1] == "broadtrack_graph.io"]
    assert not bad, "file formats imported by mathematics or metrics:\n" + "\n".join(bad)
