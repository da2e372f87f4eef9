"""``voxpose verify``: lists exactly the damaged cache files with the rule that makes each; ``--remove`` deletes
exactly those."""

import os
from pathlib import Path

import numpy as np

from tests.helpers import ROOT
from voxpose.cli.main import main
from voxpose.io.cache import producing_rules
from voxpose.io.hdf5 import write_arrays


def test_lists_and_removes_exactly_the_damaged_files(tmp_path, capsys):
    results = tmp_path / "results"
    for name in ("a/good.h5", "a/bad.h5", "b/also_bad.h5", "b/good.h5"):
        write_arrays(results / name, "mppca", {"w": np.arange(100.0)}, {})
    (results / "a/bad.h5").write_bytes((results / "a/bad.h5").read_bytes()[:500])  # truncated
    (results / "b/also_bad.h5").write_bytes((results / "b/also_bad.h5").read_bytes().replace(b"mppca", b"mppcb"))
    (results / "notes.txt").write_text("not a cache")

    assert main(["verify", str(results)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"{results / 'a/bad.h5'}: not a readable HDF5 file")
    assert out[1] == f"{results / 'b/also_bad.h5'}: content does not match its checksum (made by no rule)"
    assert len(out) == 3 and out[2].startswith("2 damaged")

    assert main(["verify", str(results), "--remove"]) == 0
    removed = capsys.readouterr().out.splitlines()[-1]
    assert removed.endswith("snakemake --forcerun results/a/bad.h5 results/b/also_bad.h5"), removed
    assert sorted(p.relative_to(results).as_posix() for p in results.rglob("*.*")) == [
        "a/good.h5", "b/good.h5", "notes.txt",
    ]  # fmt: skip
    assert main(["verify", str(results)]) == 0
    assert "every cache file matches" in capsys.readouterr().out


def test_a_missing_folder_is_a_one_line_error(tmp_path, capsys):
    assert main(["verify", str(tmp_path / "nope")]) == 2
    assert capsys.readouterr().err.strip() == f"voxpose: error: {tmp_path / 'nope'}: no such folder"


def test_rules_come_from_the_workflow():
    paths = [
        ROOT / "results/motions/walk_gen_00.h5",
        ROOT / "results/voxels/circle6/walk_gen_00.h5",
        ROOT / "results/descriptors/circle6/R0.3333-r2-4x5x10-soft/walk_gen_00.h5",
        ROOT / "results/not/a/cache.h5",
    ]
    cwd, environ = Path.cwd(), dict(os.environ)
    assert list(producing_rules(paths, ROOT).values()) == ["motion", "voxelize", "describe", None]
    assert (Path.cwd(), dict(os.environ)) == (cwd, environ)  # the workflow's setup does not leak into the caller
