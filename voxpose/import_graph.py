"""The package's own import graph, read from its source with ``ast`` (function-local imports included).

Two uses: a workflow rule's code hash is the hash of the import closure of the module it runs, so editing
any module a rule reaches, directly or not, reruns it and nothing else (Snakemake does not see edits to
the installed package); and tests/test_import_graph.py checks that imports only run down the stages.
"""

import ast
import functools
import hashlib
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parent

def module_files(root: Path = PACKAGE_DIR) -> dict[str, Path]:
    """Dotted module name -> source file, for every module of the package (packages by their ``__init__``)."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = (root.name, *path.relative_to(root).with_suffix("").parts)
        out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def _imported(module: str, path: Path, node) -> list[str]:
    """Candidate dotted names an import statement refers to (a module, or a name inside one)."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if node.level:
        package = module if path.name == "__init__.py" else module.rpartition(".")[0]
        base = package.split(".")[: len(package.split(".")) - node.level + 1]
        stem = ".".join([*base, node.module] if node.module else base)
    else:
        stem = node.module
    return [stem, *(f"{stem}.{alias.name}" for alias in node.names)]


def imports_of(module: str, files: dict[str, Path]) -> set[str]:
    """Package modules that ``module`` imports anywhere in its source, and the packages they sit in."""
    path = files[module]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import | ast.ImportFrom):
            for name in _imported(module, path, node):
                if name in files:
                    found.add(name)
                    found.update(_parents(name, files))
    found.discard(module)
    return found


def _parents(module: str, files) -> list[str]:
    """The packages a module sits in: importing it runs their ``__init__`` first."""
    parts = module.split(".")
    return [p for p in (".".join(parts[:i]) for i in range(1, len(parts))) if p in files]


@functools.cache
def import_graph(root: Path = PACKAGE_DIR) -> dict[str, frozenset[str]]:
    """Module -> the package modules it imports (the edges of the graph)."""
    files = module_files(root)
    return {m: frozenset(imports_of(m, files)) for m in files}


def closure(module: str, graph: dict | None = None) -> set[str]:
    """``module``, the packages it sits in and everything they import, directly or not."""
    graph = graph or import_graph()
    if module not in graph:
        raise KeyError(f"{module}: not a module of the package")
    seen, todo = set(), [module, *_parents(module, graph)]
    while todo:
        m = todo.pop()
        if m not in seen:
            seen.add(m)
            todo.extend(graph[m])
    return seen


def code_hash(module: str, root: Path = PACKAGE_DIR) -> str:
    """Short content hash of the import closure of ``module`` (sorted by name, so stable across runs)."""
    files = module_files(root)
    digest = hashlib.sha256()
    for m in sorted(closure(module, import_graph(root))):
        digest.update(m.encode() + b"\0" + files[m].read_bytes() + b"\0")
    return digest.hexdigest()[:16]
