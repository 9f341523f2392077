"""The package structure: the import direction assembly <- solver <- updating, and no import
circle between modules (``docs/architecture.md``). Imports are read from the source, those
inside functions included, so that a circle dodged by a local import still fails. And the
names the code and docs cite by their dotted paths exist where they are cited."""

from __future__ import annotations

import ast
import importlib
import re
from pathlib import Path

import networkx as nx
from support import ROOT

PACKAGES = ("assembly", "solver", "updating")
LAYER = {name: i for i, name in enumerate(PACKAGES)}


def _modules():
    """``{module name: path}`` of every module of the three packages."""
    out = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def _imported(module, node, modules):
    """The project modules one import statement of ``module`` names."""
    if isinstance(node, ast.Import):
        return [a.name for a in node.names if a.name in modules]
    if not isinstance(node, ast.ImportFrom):
        return []
    if node.level:  # relative: from the importing module's package, level - 1 up
        package = module if _is_package(module) else module.rpartition(".")[0]
        base = ".".join(package.split(".")[: len(package.split(".")) - node.level + 1])
        name = f"{base}.{node.module}" if node.module else base
    else:
        name = node.module or ""
    found = [f"{name}.{a.name}" for a in node.names if f"{name}.{a.name}" in modules]
    return found or ([name] if name in modules else [])


def _is_package(module):
    return (ROOT / Path(*module.split(".")) / "__init__.py").exists()


def import_graph():
    modules = _modules()
    graph = nx.DiGraph()
    graph.add_nodes_from(modules)
    for module, path in modules.items():
        for node in ast.walk(ast.parse(path.read_text())):
            for target in _imported(module, node, modules):
                if target != module:
                    graph.add_edge(module, target)
    return graph


def test_the_graph_sees_the_imports_it_must():
    """The walk finds known edges, relative and absolute (else the tests below pass empty)."""
    graph = import_graph()
    assert graph.has_edge("assembly.case", "assembly.models")  # relative import
    assert graph.has_edge("solver.substructure", "solver.joint_rules")
    assert graph.has_edge("updating.inverse.cost", "solver.substructure")
    assert graph.number_of_edges() > 100


def test_no_module_imports_its_way_back_to_itself():
    circles = [sorted(c) for c in nx.strongly_connected_components(import_graph())
               if len(c) > 1]
    assert circles == []


def test_packages_import_only_downwards():
    wrong = [(a, b) for a, b in import_graph().edges
             if LAYER[b.split(".")[0]] > LAYER[a.split(".")[0]]]
    assert wrong == []


DOTTED = re.compile(r"\b(?:assembly|solver|updating)(?:\.[A-Za-z_]\w*)+")


def _dotted_names(text):
    """Each ``package.module.name`` (and ``...name.attribute``) that ``text`` mentions."""
    return {match.group(0).rstrip(".") for match in DOTTED.finditer(text)}


def _resolves(dotted, modules):
    """Whether ``dotted`` names something: its longest prefix that is a module of the project,
    then attributes. A name whose module is a bare package (``updating.alpha.G9``: a field of
    a description) is not a reference to code and passes."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        if ".".join(parts[:cut]) in modules:
            break
    if cut < 2:
        return True
    target = importlib.import_module(".".join(parts[:cut]))
    for name in parts[cut:]:
        if not hasattr(target, name):  # a dataclass's field without a default is no attribute
            return name in getattr(target, "__dataclass_fields__", {})
        target = getattr(target, name)
    return True


def test_every_name_the_code_and_docs_cite_exists():
    """A module, function or constant cited by its dotted name in the code, the tests, the
    benches and the docs exists (the CHANGELOG, a history, aside). A name moved to another
    module and cited at its old place would mislead a reader, and a study that patches it
    there (``solver.line_ends.REACH_GROWTH_FROM = ...`` in a bench) would silently patch
    nothing."""
    modules = _modules()
    paths = [path for directory in ("assembly", "solver", "updating", "tests", "bench")
             for path in sorted((ROOT / directory).rglob("*.py"))
             if path != Path(__file__).resolve()]  # its examples of names that do not exist
    paths += sorted((ROOT / "docs").glob("*.md")) + [ROOT / "README.md", ROOT / "bench/README.md"]
    missing = sorted(f"{path.relative_to(ROOT)}: {name}" for path in paths
                     for name in _dotted_names(path.read_text(encoding="utf-8"))
                     if not _resolves(name, modules))
    assert not missing, missing


def test_a_moved_name_is_caught():
    modules = _modules()
    assert _resolves("solver.line_ends.REACH_GROWTH_FROM", modules)
    assert _resolves("solver.estimate.ErrorEstimate.plate_errors", modules)
    assert _resolves("solver.admissibility.MembraneBlock.moments", modules)  # a field
    assert not _resolves("solver.problems.REACH_GROWTH_FROM", modules)
    assert not _resolves("solver.estimate.ErrorEstimate.no_such_method", modules)
    assert _resolves("updating.alpha.G9", modules)
