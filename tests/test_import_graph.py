"""The package layout: imports only run down the stages, no circles; code hashes follow the import closure."""

import textwrap

import pytest

from voxpose.import_graph import closure, code_hash, import_graph, module_files

# The stages bottom-up: a module may import its own layer and the layers below, never one above.
LAYERS = (
    ("errors", "validation", "import_graph", "config_schema", "kernels"),
    ("io", "provenance"),
    ("motion",),
    ("voxels",),
    ("descriptors",),
    ("features",),
    ("regression",),
    ("evaluation",),
    ("apply",),
    ("cli", "workflow_config", "__main__"),
)


def layer_of(module: str) -> int:
    """Index in ``LAYERS`` of the stage a module belongs to (``voxpose`` itself is the bottom)."""
    parts = module.split(".")
    if len(parts) == 1:
        return 0
    for i, names in enumerate(LAYERS):
        if parts[1] in names:
            return i
    raise KeyError(f"{module}: in no layer of LAYERS (tests/test_import_graph.py)")


def _cycles(graph: dict) -> list[str]:
    """Modules that reach themselves (brute force: a walk from every module)."""
    out = []
    for start in graph:
        seen, todo = set(), list(graph[start])
        while todo:
            m = todo.pop()
            if m == start:
                out.append(start)
                break
            if m not in seen:
                seen.add(m)
                todo.extend(graph[m])
    return out


def _make_package(root, sources: dict):
    for name, text in sources.items():
        path = root / "pkg" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text))
    return root / "pkg"


def test_the_package_has_no_import_circle():
    assert _cycles(dict(import_graph())) == []


def test_every_import_runs_down_the_stages():
    upward = [
        f"{m} -> {t}"
        for m, targets in import_graph().items()
        for t in targets
        if layer_of(t) > layer_of(m)
    ]
    assert upward == []


def test_every_module_sits_in_a_layer_and_every_stage_is_a_package():
    files = module_files()
    for m in files:
        layer_of(m)  # raises for a module outside LAYERS
    packages = {m.split(".")[1] for m, p in files.items() if p.name == "__init__.py" and m != "voxpose"}
    assert packages == {"io", "motion", "voxels", "descriptors", "features", "regression", "evaluation", "apply", "cli"}
    assert packages <= {name for layer in LAYERS for name in layer}


def test_the_walk_sees_function_local_relative_and_aliased_imports(tmp_path):
    pkg = _make_package(
        tmp_path,
        {
            "__init__.py": "",
            "a.py": "def f():\n    from .b import g\n    return g\n",
            "b.py": "import pkg.sub.c as c\n",
            "sub/__init__.py": "",
            "sub/c.py": "from .. import d\n",
            "d.py": "X = 1\n",
            "unused.py": "from pkg import a\n",
        },
    )
    graph = import_graph(pkg)
    # module names are rooted at the folder's name
    assert closure("pkg.a", graph) == {"pkg", "pkg.a", "pkg.b", "pkg.sub", "pkg.sub.c", "pkg.d"}
    assert "pkg.unused" not in closure("pkg.a", graph)
    assert _cycles(dict(graph)) == []


def test_the_walk_finds_a_planted_circle(tmp_path):
    pkg = _make_package(
        tmp_path,
        {
            "__init__.py": "",
            "a.py": "from pkg import b\n",
            "b.py": "def f():\n    from pkg.c import x\n",
            "c.py": "import pkg.a\n",
        },
    )
    assert sorted(_cycles(dict(import_graph(pkg)))) == ["pkg.a", "pkg.b", "pkg.c"]


def test_code_hash_changes_with_any_module_in_the_closure_and_only_those(tmp_path):
    pkg = _make_package(
        tmp_path,
        {
            "__init__.py": "",
            "a.py": "from pkg import b\n",
            "b.py": "def f():\n    from pkg import c\n",
            "c.py": "",
            "d.py": "",
        },
    )
    import_graph.cache_clear()
    before = code_hash("pkg.a", pkg)
    (pkg / "d.py").write_text("# edited\n")
    import_graph.cache_clear()
    assert code_hash("pkg.a", pkg) == before  # d is not reached from a
    (pkg / "c.py").write_text("# edited\n")
    import_graph.cache_clear()
    assert code_hash("pkg.a", pkg) != before  # c is reached through b's function-local import
    import_graph.cache_clear()


def test_closure_of_an_unknown_module_is_an_error():
    with pytest.raises(KeyError, match="voxpose.nope"):
        closure("voxpose.nope")


def test_a_command_hashes_what_it_runs_indirectly():
    # `voxpose derive` runs through the heading curves it shares with the generator, the joint maps, the loader and
    # the kinematics
    # (a hand-written list once named only its own module and the BVH reader)
    reached = closure("voxpose.cli.derive")
    for module in ("motion.derive", "motion.paths", "motion.joint_map", "motion.load", "motion.bvh_kinematics",
                   "motion.rotations", "motion.canon", "io.bvh", "io.atomic"):  # fmt: skip
        assert f"voxpose.{module}" in reached
    assert "voxpose.regression.mvrvm" not in reached and "voxpose.cli.regress" not in reached
